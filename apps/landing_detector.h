#pragma once
// Touchdowns of one foot and their impact figures, from its vertical ground force sampled
// once per time step (apps/humanoid_simulation.h: landings.csv).

#include <filesystem>
#include <vector>

namespace plantar::app {

/// Subsection "Output" entries of the landing figures.
struct LandingParameters {
  double threshold = 1.0; ///< N: a touchdown is F_z rising from below to >= this, > 0
  double window = 0.05;   ///< s: the figures cover (t_touchdown, t_touchdown + window], > 0
};

/// One landing's figures (SI units).
struct Landing {
  double time = 0;              ///< s: touchdown, F_z = threshold (linear between samples)
  double impulse = 0;           ///< N s: sum F_z,n dt over the window's samples (plain
                                ///< impulse, the weight's share m g window not removed)
  double peak_force = 0;        ///< N: max F_z,n in the window
  double peak_time = 0;         ///< s: its sample time
  double rise_time = 0;         ///< s: F_z from 10 % to 90 % of peak_force (first crossings,
                                ///< linear between samples)
  double peak_acceleration = 0; ///< max |a_n| in the window (the filtered waist a_z), m/s^2
  double window = 0;            ///< s covered: the window, shorter if the run ended in it
};

/// Feed it every sample (t_n = t_0 + n dt, F_z,n, a_n) with update(); call finish() at the
/// end. A touchdown needs a sample below the threshold before it (a foot loaded at the first
/// sample has not landed). During a window no new touchdown is detected (a bounce belongs to
/// its landing); after it, the foot must go below the threshold again. If F_z,n-1 >= 10 % of
/// the peak already, the 10 % crossing is taken at t_n-1. The force sample F_z,n is the mean
/// over (t_n-1, t_n] (the step's impulse / dt), so the impulse is exact for simulated forces.
/// Everything is allocated by the constructor; update() allocates nothing.
class LandingDetector {
public:
  LandingDetector() = default;
  /// @p period dt [s] > 0; @p max_samples: the most update() calls (reserves max_samples / 2
  /// + 1 landings, the most possible). Throws std::invalid_argument on a bad parameter.
  LandingDetector(const LandingParameters& params, double period, int max_samples);
  /// One sample at time @p t [s]: vertical force @p force_z [N], acceleration @p acceleration.
  void update(double t, double force_z, double acceleration);
  /// Closes a window still open (its Landing::window is then shorter).
  void finish();
  const std::vector<Landing>& landings() const { return landings_; }

private:
  enum class State { unarmed, armed, window, loaded };
  void close_window();
  double crossing(double level) const;
  LandingParameters params_;
  double period_ = 0;
  State state_ = State::unarmed;
  double t_previous_ = 0, f_previous_ = 0;
  int n_buffer_ = 0;
  std::vector<double> times_, forces_; ///< the window: the sample before touchdown, then its own
  Landing current_;
  std::vector<Landing> landings_;
};

/// Writes landings.csv at @p path atomically: one row per landing in time order, columns
/// foot (0: right, 1: left), t, impulse, peak_force, peak_time, rise_time, peak_az_filtered,
/// window (Landing's fields, SI units).
void write_landings_csv(const std::vector<Landing>& right, const std::vector<Landing>& left,
                        const std::filesystem::path& path);

} // namespace plantar::app
