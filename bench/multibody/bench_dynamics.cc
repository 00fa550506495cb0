// Microseconds per RNEA, CRBA and time step on the HRP-2-like model (36 DoF with the free
// base; 42 with compliant ankles). Not a regression test: figures depend on the machine and
// its load. For controlled measurements run on an idle machine with
//   --benchmark_repetitions=10 --benchmark_min_time=0.5
// and compare medians. Published reference (validation.md, Pinocchio, 34-DoF humanoid, one
// core): RNEA ~3.7 us, CRBA ~3.0 us; MuJoCo humanoid (27 DoF, ~12 contacts) ~31 us per step.
#include "multibody/crba.h"
#include "multibody/data.h"
#include "multibody/kinematics.h"
#include "multibody/rnea.h"
#include "multibody/stepper.h"
#include "multibody/urdf_loader.h"

#include <benchmark/benchmark.h>

#include <cstdio>
#include <random>
#include <string>

namespace plantar::multibody {
namespace {

std::string hrp2_path() {
  return std::string(PLANTAR_SOURCE_DIR) + "/models/hrp2/hrp2.urdf";
}

/// Loads the URDF once per process.
const Model& hrp2(bool compliant_ankles) {
  static const Model rigid = build_model_from_urdf(hrp2_path());
  static const Model compliant = [] {
    ModelOptions options;
    options.compliant_ankle.foot_links = {"RLEG_LINK5", "LLEG_LINK5"};
    return build_model_from_urdf(hrp2_path(), options);
  }();
  return compliant_ankles ? compliant : rigid;
}

Eigen::VectorXd random_state(const Model& model, int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::VectorXd x(n);
  for (int k = 0; k < n; ++k) {
    x[k] = uniform(rng);
  }
  return x;
}

Eigen::VectorXd random_configuration(const Model& model) {
  Eigen::VectorXd q = random_state(model, model.nq, 1);
  q.segment<4>(3).normalize();
  return q;
}

void BM_Rnea(benchmark::State& state) {
  const Model& model = hrp2(false);
  Data data(model);
  const Eigen::VectorXd q = random_configuration(model);
  const Eigen::VectorXd v = random_state(model, model.nv, 2);
  const Eigen::VectorXd a = random_state(model, model.nv, 3);
  for (auto _ : state) {
    benchmark::DoNotOptimize(rnea(model, data, q, v, a).data());
  }
}
BENCHMARK(BM_Rnea)->Unit(benchmark::kMicrosecond);

void BM_Crba(benchmark::State& state) {
  const Model& model = hrp2(false);
  Data data(model);
  const Eigen::VectorXd q = random_configuration(model);
  for (auto _ : state) {
    benchmark::DoNotOptimize(crba(model, data, q).data());
  }
}
BENCHMARK(BM_Crba)->Unit(benchmark::kMicrosecond);

void BM_ForwardKinematics(benchmark::State& state) {
  const Model& model = hrp2(false);
  Data data(model);
  const Eigen::VectorXd q = random_configuration(model);
  const Eigen::VectorXd v = random_state(model, model.nv, 2);
  for (auto _ : state) {
    forward_kinematics(model, data, q, v);
    benchmark::DoNotOptimize(data.v.back().data());
  }
}
BENCHMARK(BM_ForwardKinematics)->Unit(benchmark::kMicrosecond);

/// Full steps of the robot standing under PD control: range(0) = 0 without contacts (in the
/// air), 1 with 8 rigid sole-corner contacts; range(1) = 1 with compliant ankles; range(2) = 1
/// with StepperParameters::midpoint_bias.
void BM_Step(benchmark::State& state) {
  const bool contacts = state.range(0) != 0;
  const bool compliant = state.range(1) != 0;
  const Model& model = hrp2(compliant);
  StepperParameters parameters;
  parameters.time_step = 1e-3;
  parameters.midpoint_bias = state.range(2) != 0;
  Stepper stepper(model, parameters);
  stepper.set_gains(PdGains::Uniform(model, 1e4, 200.0));
  Data data(model);
  Eigen::VectorXd q = model.neutral_configuration();
  forward_kinematics(model, data, q);
  const int sole = model.frame_id("r_sole");
  q[2] = -frame_placement(model, data, sole).translation.z() + (contacts ? 0.0 : 1.0);
  if (contacts) {
    for (const char* name : {"r_sole", "l_sole"}) {
      const Frame& frame = model.frames[model.frame_id(name)];
      for (const double x : {-0.1086, 0.1086}) {
        for (const double y : {-0.069, 0.069}) {
          stepper.add_contact_point(frame.body, frame.placement.act_point(Eigen::Vector3d(x, y, 0)),
                                    0.8);
        }
      }
    }
  }
  const Eigen::VectorXd q_ref = q;
  Eigen::VectorXd v = Eigen::VectorXd::Zero(model.nv);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.nv);
  for (int n = 0; n < 200; ++n) { // settle
    stepper.step(q, v, zero, q_ref, zero);
  }
  const Eigen::VectorXd q0 = q, v0 = v;
  int n_contacts = 0;
  int steps = 0;
  for (auto _ : state) {
    if (!contacts && ++steps % 1000 == 0) { // stay near the start while falling freely
      state.PauseTiming();
      q = q0;
      v = v0;
      state.ResumeTiming();
    }
    n_contacts = stepper.step(q, v, zero, q_ref, zero).n_contacts;
  }
  state.counters["nv"] = model.nv;
  state.counters["contacts"] = n_contacts;
}
BENCHMARK(BM_Step)->Args({0, 0, 0})->Args({1, 0, 0})->Args({1, 1, 0})->Args({1, 0, 1})->Unit(
    benchmark::kMicrosecond);

} // namespace
} // namespace plantar::multibody

int main(int argc, char** argv) {
  std::printf("Plantar multibody, HRP-2-like model (nv = 36 with the free base, 42 with compliant "
              "ankles).\nPublished (validation.md): Pinocchio 34-DoF humanoid RNEA ~3.7 us, CRBA "
              "~3.0 us; MuJoCo 27-DoF humanoid ~31 us per step with ~12 contacts.\n\n");
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
