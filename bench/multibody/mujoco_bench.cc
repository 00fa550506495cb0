// The rigid robot in MuJoCo (Debian's libmujoco, C API), for the side-by-side comparison of
// bench/multibody/mujoco_compare.py: the model generated from the scene's URDF, its joints
// driven by the joint references Plantar recorded (joints.csv, columns <joint>_ref), one
// record per step kept in memory like Plantar's time series, written after the loop.
//
//   mujoco_bench MODEL.xml JOINTS.csv WAIST.csv OUT.csv [--steps N] [--fall-height H]
//
// The actuators are MuJoCo position servos (force kp (ctrl - q)) with the joint damping
// kd + dt kp, which MuJoCo's Euler integrator applies at the step's end velocity v+, and
// ctrl = q_ref + (kd / kp) v_ref: tau = kp (q_ref - q) + kd v_ref - (kd + dt kp) v+, Plantar's
// linear-implicit PD at theta = 1 (kp (q_ref - q+) + kd (v_ref - v+), q+ = q + dt v+;
// multibody/stepper.h), v_ref = (q_ref,k - q_ref,k-1) / dt as in apps/humanoid_simulation.cc.
// Initial state: the first reference row, the base at WAIST.csv's first (x, y), identity
// orientation, the lowest contact point on z = 0, at rest. Prints name,value lines: the loop's us
// per step and the physical figures (contact force sum and weight, N; CoM and base heights, m),
// averaged over the last 0.5 s, and the time the base first went below H (default 0.4 m, the
// scenes' Simulation/Fall height; -1: never) with the us per step before it.
#include <mujoco/mujoco.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

struct Table {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  int column(const std::string& name, const std::string& file) const {
    const auto it = std::find(columns.begin(), columns.end(), name);
    if (it == columns.end())
      throw std::runtime_error(file + ": no column '" + name + "'");
    return static_cast<int>(it - columns.begin());
  }
};

Table read_csv(const std::string& file) {
  std::ifstream in(file);
  if (!in)
    throw std::runtime_error(file + ": cannot open");
  Table table;
  std::string line, cell;
  std::getline(in, line);
  std::istringstream header(line);
  while (std::getline(header, cell, ','))
    table.columns.push_back(cell);
  while (std::getline(in, line)) {
    std::istringstream row(line);
    std::vector<double> values;
    while (std::getline(row, cell, ','))
      values.push_back(std::strtod(cell.c_str(), nullptr));
    if (values.size() != table.columns.size())
      throw std::runtime_error(file + ": a row of " + std::to_string(values.size()) +
                               " values, the header has " + std::to_string(table.columns.size()));
    table.rows.push_back(std::move(values));
  }
  if (table.rows.empty())
    throw std::runtime_error(file + ": no rows");
  return table;
}

int run(int argc, char** argv) {
  if (argc < 5) {
    std::cerr << "usage: mujoco_bench MODEL.xml JOINTS.csv WAIST.csv OUT.csv [--steps N] "
                 "[--fall-height H]\n";
    return 2;
  }
  const std::string model_file = argv[1], joints_file = argv[2], waist_file = argv[3],
                    out_file = argv[4];
  long max_steps = -1;
  double fall_height = 0.4;
  for (int i = 5; i + 1 < argc; i += 2) {
    if (std::string(argv[i]) == "--steps")
      max_steps = std::atol(argv[i + 1]);
    else if (std::string(argv[i]) == "--fall-height")
      fall_height = std::atof(argv[i + 1]);
    else
      throw std::runtime_error(std::string("unknown option ") + argv[i]);
  }
  char error[1000] = "";
  mjModel* m = mj_loadXML(model_file.c_str(), nullptr, error, sizeof(error));
  if (!m)
    throw std::runtime_error(model_file + ": " + error);
  mjData* d = mj_makeData(m);
  const double dt = m->opt.timestep;

  // Reference: column <joint>_ref of each actuator's joint, one row per step.
  const Table joints = read_csv(joints_file);
  const Table waist = read_csv(waist_file);
  const int nu = m->nu;
  std::vector<int> ref_column(nu), qpos_index(nu), dof_index(nu);
  std::vector<double> kd(nu), kd_over_kp(nu);
  for (int a = 0; a < nu; ++a) {
    const int joint = m->actuator_trnid[2 * a];
    const std::string name = mj_id2name(m, mjOBJ_JOINT, joint);
    ref_column[a] = joints.column(name + "_ref", joints_file);
    qpos_index[a] = m->jnt_qposadr[joint];
    dof_index[a] = m->jnt_dofadr[joint];
    const double kp = m->actuator_gainprm[a * mjNGAIN];
    kd[a] = m->dof_damping[dof_index[a]] - dt * kp;
    kd_over_kp[a] = kd[a] / kp;
  }
  const long n_steps =
      max_steps > 0 ? std::min<long>(max_steps, joints.rows.size()) : joints.rows.size();
  std::vector<double> ctrl(n_steps * nu);
  for (long k = 0; k < n_steps; ++k) {
    const auto& row = joints.rows[k];
    const auto& previous = joints.rows[k > 0 ? k - 1 : 0];
    for (int a = 0; a < nu; ++a) {
      const double q_ref = row[ref_column[a]];
      const double v_ref = (q_ref - previous[ref_column[a]]) / dt;
      ctrl[k * nu + a] = q_ref + kd_over_kp[a] * v_ref;
    }
  }

  // Initial state: the first reference, base at (x, y) of the first waist row, soles on z = 0.
  mj_resetData(m, d);
  for (int a = 0; a < nu; ++a)
    d->qpos[qpos_index[a]] = joints.rows[0][ref_column[a]];
  d->qpos[0] = waist.rows[0][waist.column("x", waist_file)];
  d->qpos[1] = waist.rows[0][waist.column("y", waist_file)];
  d->qpos[2] = 0;
  d->qpos[3] = 1;
  d->qpos[4] = d->qpos[5] = d->qpos[6] = 0;
  mj_kinematics(m, d);
  double lowest = 1e300;
  for (int g = 0; g < m->ngeom; ++g) {
    if (m->geom_type[g] == mjGEOM_SPHERE)
      lowest = std::min(lowest, d->geom_xpos[3 * g + 2] - m->geom_size[3 * g]);
    if (m->geom_type[g] == mjGEOM_BOX) // axis-aligned at the start (feet flat)
      lowest = std::min(lowest, d->geom_xpos[3 * g + 2] - m->geom_size[3 * g + 2]);
  }
  d->qpos[2] = -lowest;

  // Records per step (in memory, as Plantar's TimeSeries): t, base (x, y, z), CoM (x, y, z),
  // contact force sum (world), number of contacts; every actuated joint's q, ctrl, force.
  const int n_fixed = 9, width = n_fixed + 3 * nu;
  std::vector<double> record(n_steps * width);
  const int robot = 1;                  // the base body: its subtree is the robot
  std::vector<double> elapsed(n_steps); // s since the start, after each step
  const auto start = std::chrono::steady_clock::now();
  for (long k = 0; k < n_steps; ++k) {
    std::copy_n(&ctrl[k * nu], nu, d->ctrl);
    mj_step(m, d);
    double* r = &record[k * width];
    r[0] = d->time;
    r[1] = d->qpos[0];
    r[2] = d->qpos[1];
    r[3] = d->qpos[2];
    r[4] = d->subtree_com[3 * robot];
    r[5] = d->subtree_com[3 * robot + 1];
    r[6] = d->subtree_com[3 * robot + 2];
    double sum[3] = {0, 0, 0};
    for (int c = 0; c < d->ncon; ++c) {
      mjtNum local[6], world[3];
      mj_contactForce(m, d, c, local);
      mju_mulMatTVec(world, d->contact[c].frame, local, 3, 3); // frame rows: normal, t1, t2
      // The force on the robot: contact c acts on geom2 from geom1 (the floor is geom 0).
      const double sign = d->contact[c].geom1 == 0 ? 1.0 : -1.0;
      for (int i = 0; i < 3; ++i)
        sum[i] += sign * world[i];
    }
    r[7] = sum[2];
    r[8] = d->ncon;
    for (int a = 0; a < nu; ++a) {
      r[n_fixed + 3 * a] = d->qpos[qpos_index[a]];
      r[n_fixed + 3 * a + 1] = d->ctrl[a];
      r[n_fixed + 3 * a + 2] = d->actuator_force[a] - kd[a] * d->qvel[dof_index[a]]; // as Plantar
    }
    elapsed[k] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  {
    const std::string temporary = out_file + ".tmp";
    std::ofstream out(temporary);
    out << "t,x,y,z,com_x,com_y,com_z,contact_fz,n_contacts";
    for (int a = 0; a < nu; ++a) {
      const std::string name = mj_id2name(m, mjOBJ_JOINT, m->actuator_trnid[2 * a]);
      out << "," << name << "_q," << name << "_ref," << name << "_tau";
    }
    out << "\n";
    out.precision(17);
    for (long k = 0; k < n_steps; ++k) {
      for (int c = 0; c < width; ++c)
        out << (c ? "," : "") << record[k * width + c];
      out << "\n";
    }
    out.close();
    if (!out || std::rename(temporary.c_str(), out_file.c_str()) != 0)
      throw std::runtime_error(out_file + ": cannot write");
  }

  // Figures: averages over the last 0.5 s.
  const long window = std::min<long>(n_steps, std::lround(0.5 / dt));
  double force = 0, com_z = 0, base_z = 0, contacts = 0;
  for (long k = n_steps - window; k < n_steps; ++k) {
    force += record[k * width + 7] / window;
    com_z += record[k * width + 6] / window;
    base_z += record[k * width + 3] / window;
    contacts += record[k * width + 8] / window;
  }
  double mass = 0;
  for (int b = 1; b < m->nbody; ++b)
    mass += m->body_mass[b];
  double fall_time = -1;  // the first base height below fall_height (-1: none)
  long upright = n_steps; // steps before the fall
  for (long k = 0; k < n_steps && fall_time < 0; ++k)
    if (record[k * width + 3] < fall_height) {
      fall_time = record[k * width];
      upright = std::max(1L, k);
    }

  // Plantar's CoM height at its last recorded step (WAIST.csv pose, JOINTS.csv angles), by
  // MuJoCo's kinematics of the same model.
  const auto& w = waist.rows.back();
  const double half_roll = 0.5 * w[waist.column("roll", waist_file)],
               half_pitch = 0.5 * w[waist.column("pitch", waist_file)],
               half_yaw = 0.5 * w[waist.column("yaw", waist_file)];
  const double cr = std::cos(half_roll), sr = std::sin(half_roll), cp = std::cos(half_pitch),
               sp = std::sin(half_pitch), cy = std::cos(half_yaw), sy = std::sin(half_yaw);
  d->qpos[0] = w[waist.column("x", waist_file)];
  d->qpos[1] = w[waist.column("y", waist_file)];
  d->qpos[2] = w[waist.column("z", waist_file)];
  d->qpos[3] = cr * cp * cy + sr * sp * sy; // R = Rz(yaw) Ry(pitch) Rx(roll)
  d->qpos[4] = sr * cp * cy - cr * sp * sy;
  d->qpos[5] = cr * sp * cy + sr * cp * sy;
  d->qpos[6] = cr * cp * sy - sr * sp * cy;
  for (int a = 0; a < nu; ++a) {
    const std::string name = mj_id2name(m, mjOBJ_JOINT, m->actuator_trnid[2 * a]);
    d->qpos[qpos_index[a]] = joints.rows.back()[joints.column(name + "_q", joints_file)];
  }
  mj_kinematics(m, d);
  mj_comPos(m, d);
  std::printf("us_per_step,%.4f\nn_steps,%ld\nweight,%.6f\ncontact_fz,%.6f\ncom_z,%.6f\n"
              "base_z,%.6f\nmean_contacts,%.3f\nplantar_final_com_z,%.6f\nfall_time,%.4f\nus_per_"
              "step_upright,%.4f\n",
              1e6 * seconds / n_steps, n_steps, -mass * m->opt.gravity[2], force, com_z, base_z,
              contacts, d->subtree_com[3 * robot + 2], fall_time,
              1e6 * elapsed[upright - 1] / upright);
  mj_deleteData(d);
  mj_deleteModel(m);
  return 0;
}

} // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "mujoco_bench: " << e.what() << "\n";
    return 1;
  }
}
