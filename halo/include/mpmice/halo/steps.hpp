#pragma once
/// \file steps.hpp
/// \brief The timestep as an ordered list of steps that declare what they read (with
///        a ghost depth) and write; the runner refreshes exactly the stale ghosts a
///        step needs before running it, and times it (architecture.md, "The cycle").
///
/// A step gets its fields only through its StepContext, which refuses a field the
/// step did not declare (std::logic_error naming step and field). The check is a
/// name lookup per access, not per cell, so it stays on in every build type.
#include <functional>
#include <iosfwd>
#include <map>
#include <string>
#include <variant>
#include <vector>

#include <mpmice/halo/halo.hpp>

namespace mpmice {

/// A field a step reads, and how many ghost layers of it must be valid.
struct FieldRead {
  std::string field;
  int ghosts = 0;
};

/// A field a step writes; `valid_ghosts` > 0 if the step computes that many ghost
/// layers itself (redundantly), so that no exchange is needed for them.
/// `sum_ghosts` > 0 for a scatter (particle-to-grid): the step adds into that many
/// ghost layers, and the runner then sums them into the patches that own them.
struct FieldWrite {
  std::string field;
  int valid_ghosts = 0;
  int sum_ghosts = 0;
};

/// Named grid fields with their location and how many ghost layers are valid.
class FieldRegistry {
 public:
  void add(const std::string& name, const Field4& view, Location loc);
  void add(const std::string& name, const Field3& view, Location loc);
  bool contains(const std::string& name) const { return m_entries.count(name) > 0; }
  Location location(const std::string& name) const { return entry(name).loc; }
  int valid_ghosts(const std::string& name) const { return entry(name).valid_ghosts; }
  void set_valid_ghosts(const std::string& name, int g) { entry(name).valid_ghosts = g; }
  /// Exchange the views (and ghost states) of two fields, e.g. new state -> old state.
  void swap(const std::string& a, const std::string& b);
  /// Unchecked access, for set-up and output code outside the steps.
  template <class V>
  V get(const std::string& name) const {
    const Entry& e = entry(name);
    if (!std::holds_alternative<V>(e.view))
      throw std::logic_error("field '" + name + "' is not of the requested view type");
    return std::get<V>(e.view);
  }
  std::vector<std::string> names() const;

 private:
  friend class StepRunner;
  struct Entry {
    std::variant<Field4, Field3> view;
    Location loc = Location::cell;
    int valid_ghosts = 0;
  };
  const Entry& entry(const std::string& name) const;
  Entry& entry(const std::string& name);
  std::map<std::string, Entry> m_entries;
};

struct Step;

/// What a running step may touch: its declared reads (read-only views) and writes.
class StepContext {
 public:
  StepContext(const Step& step, const FieldRegistry& fields) : m_step(step), m_fields(fields) {}
  /// A declared read (or a field the step writes), as a read-only view.
  template <class V>
  typename V::const_type read(const std::string& name) const {
    check(name, false);
    return m_fields.get<V>(name);
  }
  /// A declared write.
  template <class V>
  V write(const std::string& name) const {
    check(name, true);
    return m_fields.get<V>(name);
  }
  const Step& step() const { return m_step; }

 private:
  void check(const std::string& name, bool writing) const;
  const Step& m_step;
  const FieldRegistry& m_fields;
};

/// One step of the cycle.
struct Step {
  std::string name;
  std::vector<FieldRead> reads;
  std::vector<FieldWrite> writes;
  std::function<void(const StepContext&)> run;
};

/// Wall-clock totals of one step on this rank.
struct StepTiming {
  std::string name;
  long calls = 0;
  double seconds = 0;        ///< ghost refresh + kernels
  double ghost_seconds = 0;  ///< ghost refresh alone
};

/// Runs steps in the order given, refreshing stale ghosts first.
class StepRunner {
 public:
  StepRunner(Halo& halo, FieldRegistry& fields) : m_halo(halo), m_fields(fields) {}

  /// Throw std::logic_error if the step names an unknown field or needs more ghost
  /// layers than the patch has.
  void validate(const Step& step) const;
  void run(const Step& step);

  const std::vector<StepTiming>& timings() const { return m_timings; }
  /// Ghost refreshes (one per field and step) done so far.
  long ghost_refreshes() const { return m_refreshes; }
  /// A table of the per-step times, slowest rank's view if called on every rank
  /// (collective over the decomposition's communicator); printed by rank 0.
  void print_timings(std::ostream& out) const;

 private:
  Halo& m_halo;
  FieldRegistry& m_fields;
  std::vector<StepTiming> m_timings;
  std::map<std::string, std::size_t> m_timing_index;
  long m_refreshes = 0;
};

}  // namespace mpmice
