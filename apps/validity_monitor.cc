#include "apps/validity_monitor.h"

#include <sstream>
#include <stdexcept>

namespace plantar::app {

void ValidityMonitor::check(const ValidityLimit& limit, double value, const char* detail) {
  ValidityRecord* record = nullptr;
  for (int i = 0; i < n_records_; ++i)
    if (records_[i].id == &limit) {
      record = &records_[i];
      break;
    }
  if (!record) {
    if (n_records_ == max_limits)
      throw std::logic_error("ValidityMonitor: more than max_limits limits");
    record = &records_[n_records_++];
    record->id = &limit;
    record->limit = limit;
    record->peak = value;
    record->peak_time = time_;
  }
  ++record->n_checks;
  // NaN is past every level: a model that reports NaN has left its validity.
  const bool nan = !(value == value);
  if (nan || limit.past(value, record->peak)) {
    record->peak = value;
    record->peak_time = time_;
  }
  if (nan || limit.past(value, limit.warning)) {
    if (record->n_warning_steps == 0) {
      record->first_warning_step = step_;
      record->first_warning_time = time_;
      record->first_warning_value = value;
    }
    ++record->n_warning_steps;
  }
  if (nan || limit.past(value, limit.failure)) {
    std::ostringstream msg;
    msg << limit.quantity << " = " << value << (*detail ? " (" : "") << detail
        << (*detail ? ")" : "") << (limit.bound == ValidityLimit::Bound::upper ? " > " : " < ")
        << limit.failure_parameter << " = " << limit.failure << ": " << limit.remedy;
    throw std::runtime_error(msg.str());
  }
}

int ValidityMonitor::n_warnings() const {
  int n = 0;
  for (int i = 0; i < n_records_; ++i)
    n += records_[i].warned() ? 1 : 0;
  return n;
}

std::string ValidityMonitor::warning_text() const {
  std::ostringstream out;
  for (int i = 0; i < n_records_; ++i) {
    const ValidityRecord& r = records_[i];
    if (!r.warned())
      continue;
    const char* side = r.limit.bound == ValidityLimit::Bound::upper ? "above" : "below";
    out << "warning: " << r.limit.quantity << " " << side << " " << r.limit.warning_parameter
        << " = " << r.limit.warning << ": first at step " << r.first_warning_step
        << ", t = " << r.first_warning_time << " s (" << r.first_warning_value << "), peak "
        << r.peak << " at t = " << r.peak_time << " s, " << r.n_warning_steps << " of "
        << r.n_checks << " steps past it\n";
  }
  return out.str();
}

} // namespace plantar::app
