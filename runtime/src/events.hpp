// The model's events during a run (Model::event_count): their modes set from
// the signs of the zero-crossing functions at the start, switched where an
// integrator locates a crossing, and every switch logged for the run summary
// and --event-log.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "contacts.hpp"
#include "mbgrt/model.hpp"

namespace mbgrt::detail {

struct EventRecord {
  double t = 0.0;
  std::size_t index = 0;  ///< which event (Model::event_name)
  bool on = false;        ///< its step switched on (x rose through 0) or off
  bool jump = false;      ///< the unknowns jumped there (Model::event_jump, a contact's impact)
  std::string note;       ///< a contact's: what happened ("impact at 4.43 m/s: bounces")
  const char* what = nullptr;  ///< a contact's: what happened in a word (Contacts::state); else null
  /// The event log's state: a contact's word, else "on" or "off".
  const char* state() const { return what ? what : on ? "on" : "off"; }
};

class Events {
 public:
  explicit Events(Model& model) : model_(model), n_(model.event_count()), g_(n_), contacts_(model) {}

  std::size_t count() const { return n_; }
  Model& model() { return model_; }

  /// While on, an integrator's advance_to returns at the first instant it
  /// fires events at, short of its target (an FMU's early return from a
  /// co-simulation step, at the event).
  void pause_at_events(bool on) { pause_ = on; }
  bool pausing() const { return pause_; }

  /// The zero-crossing functions at (t, y[, yp]); false if one is not finite.
  bool functions(double t, const double* y, const double* yp, double* g);
  /// Each mode from the sign of its function at the start of the run (x >= 0:
  /// on, as step(x) is), a contact's from its gap (Contacts::start); not logged.
  bool start(double t, const double* y, const double* yp);
  /// Event k's function crossed zero at t, rising (on) or falling: switches
  /// its mode, lets the model change y (Model::event_jump) and logs it. False
  /// if the mode already was so (nothing logged). A contact's event does what
  /// Contacts::fire says (an impact changes y).
  bool fire(double t, std::size_t k, bool on, double* y);
  const Contacts& contacts() const { return contacts_; }
  Contacts& contacts() { return contacts_; }
  /// More than kMaxAtOneInstant switches (or root reports) at one time: the
  /// modes chatter (a relation that turns itself off when on), and the run
  /// must stop.
  bool chattering() const { return at_instant_ > kMaxAtOneInstant || roots_at_instant_ > kMaxAtOneInstant; }
  static constexpr long kMaxAtOneInstant = 100;
  /// One event switched kZenoCount times in a row, each sooner after the one
  /// before than that one was after its own, the last within kZenoInterval
  /// (times max(1, |t|)): its switches accumulate (Zeno's bouncing ball)
  /// and will soon be closer than a root finder can tell apart.
  bool accumulating() const { return zeno_event_ >= 0; }
  std::size_t accumulating_event() const { return static_cast<std::size_t>(zeno_event_); }
  /// Time between event k's last two switches (NaN before its second).
  double last_interval(std::size_t k) const { return last_dt_[k]; }
  static constexpr long kZenoCount = 10;
  static constexpr double kZenoInterval = 1e-6;
  /// A root finder reported crossings at t (switching something or not).
  void note_roots(double t);

  const std::vector<EventRecord>& log() const { return log_; }

  /// What a run has changed here besides the model (each contact's mode, the
  /// switches' timing that tells chattering and Zeno's accumulation), as
  /// numbers appended to `out`, for an FMU's saved state; restore() reads
  /// them back from `in` (the same count), for a run that goes on from there.
  void save(std::vector<double>& out) const;
  void restore(const double*& in);
  /// How many numbers save() appends.
  std::size_t saved_size() const { return 6 + 4 * n_ + 2 * contacts_.count(); }
  /// "t = 0.5 s: step(t - t_bump) (time event) on"
  std::string describe(const EventRecord& e) const;
  /// Event k in model terms (Model::event_name).
  std::string model_name(std::size_t k) const { return model_.event_name(k); }

  /// The stored energy the jumps took (Model::stored_energy before less
  /// after, summed): the energy witness counts it as absorbed. Counted once
  /// the witness asks for it (GuardedModel::enable_energy_witness).
  double jumped_energy() const { return jumped_energy_; }
  void count_jumped_energy() { count_jumped_energy_ = true; }

 private:
  Model& model_;
  void record(double t, std::size_t k, bool on, bool jump, std::string note, const char* what = nullptr);
  bool switch_and_jump(double t, std::size_t k, bool on, double* y);
  double jumped_energy_ = 0.0;
  bool count_jumped_energy_ = false;

  std::size_t n_;
  std::vector<double> g_;
  std::vector<EventRecord> log_;
  Contacts contacts_;
  double instant_ = 0.0;  ///< time of the latest switch
  bool pause_ = false;    ///< pause_at_events
  long at_instant_ = 0;   ///< switches at that time
  double root_instant_ = 0.0;
  long roots_at_instant_ = 0;      ///< root reports at root_instant_
  std::vector<double> last_t_;     ///< per event: when it last switched (NaN: never)
  std::vector<double> last_dt_;    ///< per event: the interval before that switch (NaN: none)
  std::vector<long> shrinking_;    ///< per event: switches in a row, each interval shorter than the one before
  long zeno_event_ = -1;           ///< the event whose switches accumulate (-1: none)
};

}  // namespace mbgrt::detail
