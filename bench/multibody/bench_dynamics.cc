// Microseconds per RNEA, CRBA and time step on the HRP-2-like model (36 DoF with the free
// base; 42 with compliant ankles). Not a regression test: figures depend on the machine and
// its load. For controlled measurements run on an idle machine with
//   --benchmark_repetitions=10 --benchmark_min_time=0.5
// and compare medians. Published reference (validation.md, Pinocchio, 34-DoF humanoid, one
// core): RNEA ~3.7 us, CRBA ~3.0 us; MuJoCo humanoid (27 DoF, ~12 contacts) ~31 us per step.
#include "coupling/pad_state.h"
#include "multibody/crba.h"
#include "multibody/data.h"
#include "multibody/kinematics.h"
#include "multibody/rnea.h"
#include "multibody/stepper.h"
#include "multibody/tree_factorization.h"
#include "multibody/urdf_loader.h"

#include <Eigen/Cholesky>
#include <benchmark/benchmark.h>

#include <deque>

#include <algorithm>
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

/// M + dt D + dt^2 K (36 x 36) of HRP-2 at a random configuration (dt 1 ms, D 200, K 1e4).
Eigen::MatrixXd effective_mass(const Model& model) {
  Data data(model);
  Eigen::MatrixXd m_eff = crba(model, data, random_configuration(model));
  m_eff.diagonal().array() += 0.2 + 1e-6 * 1e4;
  return m_eff;
}

/// Dense Cholesky of M + dt D + dt^2 K by Eigen's LLT (blocked), plus one solve.
void BM_EffectiveMassCholesky(benchmark::State& state) {
  const Model& model = hrp2(false);
  const Eigen::MatrixXd m_eff = effective_mass(model);
  Eigen::LLT<Eigen::MatrixXd> llt(model.nv);
  Eigen::VectorXd x = random_state(model, model.nv, 2);
  for (auto _ : state) {
    llt.compute(m_eff);
    llt.solveInPlace(x);
    benchmark::DoNotOptimize(x.data());
  }
}
BENCHMARK(BM_EffectiveMassCholesky)->Unit(benchmark::kMicrosecond);

/// The same with Eigen's unblocked in-place factorization (no blocking, no norm), as
/// Stepper::step does.
void BM_EffectiveMassCholeskyUnblocked(benchmark::State& state) {
  const Model& model = hrp2(false);
  const Eigen::MatrixXd m_eff = effective_mass(model);
  Eigen::MatrixXd l(model.nv, model.nv);
  Eigen::VectorXd x = random_state(model, model.nv, 2);
  for (auto _ : state) {
    l = m_eff;
    Eigen::internal::llt_inplace<double, Eigen::Lower>::unblocked(l);
    l.triangularView<Eigen::Lower>().solveInPlace(x);
    l.triangularView<Eigen::Lower>().transpose().solveInPlace(x);
    benchmark::DoNotOptimize(x.data());
  }
}
BENCHMARK(BM_EffectiveMassCholeskyUnblocked)->Unit(benchmark::kMicrosecond);

/// The same with the tree factorization L^T D L (multibody/tree_factorization.h), as
/// Stepper::step does by default.
void BM_EffectiveMassTreeFactorization(benchmark::State& state) {
  const Model& model = hrp2(false);
  const Eigen::MatrixXd m_eff = effective_mass(model);
  TreeFactorization tree(model);
  Eigen::VectorXd x = random_state(model, model.nv, 2);
  for (auto _ : state) {
    tree.compute(m_eff);
    tree.solve_in_place(x);
    benchmark::DoNotOptimize(x.data());
  }
}
BENCHMARK(BM_EffectiveMassTreeFactorization)->Unit(benchmark::kMicrosecond);

/// Full steps of the robot standing under PD control: range(0) = 0 without contacts (in the
/// air), 1 with 8 rigid sole-corner contacts, 2 on two compliant patches of 9 x 7 nodes (the
/// size of scenes/walk.prm's condensed soles) with a dense SPD compliance (C = 1e-7 (B B^T / 189
/// + I) m/N, B uniform in [-1, 1]; its values do not matter for the cost; the default solver
/// dominates that total, see the phase counters); range(1) = 1 with compliant ankles;
/// range(2) = 1 with StepperParameters::midpoint_bias.
void BM_Step(benchmark::State& state) {
  const bool contacts = state.range(0) != 0;
  const bool compliant = state.range(1) != 0;
  const Model& model = hrp2(compliant);
  StepperParameters parameters;
  parameters.time_step = 1e-3;
  parameters.midpoint_bias = state.range(2) != 0;
  parameters.max_contacts = 128;
  std::deque<coupling::PadState> pads; // outlive the stepper
  Stepper stepper(model, parameters);
  stepper.set_gains(PdGains::Uniform(model, 1e4, 200.0));
  Data data(model);
  Eigen::VectorXd q = model.neutral_configuration();
  forward_kinematics(model, data, q);
  const int sole = model.frame_id("r_sole");
  q[2] = -frame_placement(model, data, sole).translation.z() + (contacts ? 0.0 : 1.0);
  if (state.range(0) == 2) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    Eigen::MatrixXd b(189, 189);
    for (int i = 0; i < 189; ++i) {
      for (int j = 0; j < 189; ++j) {
        b(i, j) = uniform(rng);
      }
    }
    Eigen::MatrixXd compliance =
        1e-7 * (b * b.transpose() / 189.0 + Eigen::MatrixXd::Identity(189, 189));
    compliance = (0.5 * (compliance + compliance.transpose())).eval();
    for (const char* name : {"r_sole", "l_sole"}) {
      const Frame& frame = model.frames[model.frame_id(name)];
      Eigen::Matrix3Xd nodes(3, 63);
      for (int ix = 0; ix < 9; ++ix) {
        for (int iy = 0; iy < 7; ++iy) {
          nodes.col(7 * ix + iy) = frame.placement.act_point(
              Eigen::Vector3d(-0.1086 + 0.2172 * ix / 8.0, -0.069 + 0.138 * iy / 6.0, 0));
        }
      }
      pads.emplace_back(compliance);
      stepper.add_deformable_patch(frame.body, nodes, 0.8, pads.back());
    }
  } else if (contacts) {
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
  stepper.reset_profile();
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
  // Wall microseconds per step in the phases of StepProfile.
  const StepProfile& profile = stepper.profile();
  const double us = 1e6 / static_cast<double>(std::max(profile.n_steps, 1L));
  state.counters["dyn_us"] = profile.dynamics * us;
  state.counters["build_us"] = profile.contact_build * us;
  state.counters["sole_us"] = profile.sole_update * us;
  state.counters["solve_us"] = profile.contact_solve * us;
}
BENCHMARK(BM_Step)
    ->Args({0, 0, 0})
    ->Args({1, 0, 0})
    ->Args({1, 1, 0})
    ->Args({1, 0, 1})
    ->Args({2, 0, 0})
    ->Unit(benchmark::kMicrosecond);

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
