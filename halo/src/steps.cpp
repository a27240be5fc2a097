#include <mpmice/halo/steps.hpp>

#include <chrono>
#include <cstdio>
#include <ostream>

namespace mpmice {

void FieldRegistry::add(const std::string& name, const Field4& view, Location loc) {
  m_entries[name] = Entry{view, loc, 0};
}
void FieldRegistry::add(const std::string& name, const Field3& view, Location loc) {
  m_entries[name] = Entry{view, loc, 0};
}

const FieldRegistry::Entry& FieldRegistry::entry(const std::string& name) const {
  auto it = m_entries.find(name);
  if (it == m_entries.end()) throw std::logic_error("no field named '" + name + "'");
  return it->second;
}
FieldRegistry::Entry& FieldRegistry::entry(const std::string& name) {
  return const_cast<Entry&>(static_cast<const FieldRegistry*>(this)->entry(name));
}

void FieldRegistry::swap(const std::string& a, const std::string& b) {
  Entry& ea = entry(a);
  Entry& eb = entry(b);
  if (ea.loc != eb.loc || ea.view.index() != eb.view.index())
    throw std::logic_error("cannot swap fields '" + a + "' and '" + b + "' of different kinds");
  std::swap(ea, eb);
}

std::vector<std::string> FieldRegistry::names() const {
  std::vector<std::string> out;
  for (const auto& kv : m_entries) out.push_back(kv.first);
  return out;
}

void StepContext::check(const std::string& name, bool writing) const {
  for (const auto& w : m_step.writes)
    if (w.field == name) return;
  if (!writing)
    for (const auto& r : m_step.reads)
      if (r.field == name) return;
  throw std::logic_error("step '" + m_step.name + "' " + (writing ? "writes" : "reads") +
                         " field '" + name + "' without declaring it");
}

void StepRunner::validate(const Step& step) const {
  const int G = m_halo.decomposition().patch().ghosts;
  for (const auto& r : step.reads) {
    if (!m_fields.contains(r.field))
      throw std::logic_error("step '" + step.name + "' reads unknown field '" + r.field + "'");
    if (r.ghosts < 0 || r.ghosts > G)
      throw std::logic_error("step '" + step.name + "' needs " + std::to_string(r.ghosts) +
                             " ghost layers of '" + r.field + "', the patch has " +
                             std::to_string(G));
  }
  for (const auto& w : step.writes) {
    if (!m_fields.contains(w.field))
      throw std::logic_error("step '" + step.name + "' writes unknown field '" + w.field + "'");
    if (w.sum_ghosts < 0 || w.sum_ghosts > G)
      throw std::logic_error("step '" + step.name + "' sums " + std::to_string(w.sum_ghosts) +
                             " ghost layers of '" + w.field + "', the patch has " + std::to_string(G));
  }
}

void StepRunner::run(const Step& step) {
  using clock = std::chrono::steady_clock;
  validate(step);
  auto it = m_timing_index.find(step.name);
  if (it == m_timing_index.end()) {
    it = m_timing_index.emplace(step.name, m_timings.size()).first;
    m_timings.push_back(StepTiming{step.name});
  }
  StepTiming& t = m_timings[it->second];

  const auto t0 = clock::now();
  for (const auto& r : step.reads) {
    FieldRegistry::Entry& e = m_fields.entry(r.field);
    if (r.ghosts == 0 || e.valid_ghosts >= r.ghosts) continue;
    std::visit([&](const auto& view) { m_halo.fill(view, e.loc, r.ghosts); }, e.view);
    e.valid_ghosts = r.ghosts;
    ++m_refreshes;
  }
  const auto t1 = clock::now();
  step.run(StepContext(step, m_fields));
  Kokkos::fence();
  const auto t2 = clock::now();
  for (const auto& w : step.writes) {
    FieldRegistry::Entry& e = m_fields.entry(w.field);
    if (w.sum_ghosts > 0)
      std::visit([&](const auto& view) { m_halo.sum_into_owned(view, e.loc, w.sum_ghosts); }, e.view);
    e.valid_ghosts = w.sum_ghosts > 0 ? 0 : w.valid_ghosts;
  }
  const auto t3 = clock::now();

  t.calls += 1;
  t.ghost_seconds += std::chrono::duration<double>((t1 - t0) + (t3 - t2)).count();
  t.seconds += std::chrono::duration<double>(t3 - t0).count();
}

void StepRunner::print_timings(std::ostream& out) const {
  MPI_Comm comm = m_halo.decomposition().comm();
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  double total = 0;
  std::vector<double> secs, ghost;
  for (const auto& t : m_timings) {
    secs.push_back(t.seconds);
    ghost.push_back(t.ghost_seconds);
  }
  MPI_Allreduce(MPI_IN_PLACE, secs.data(), int(secs.size()), MPI_DOUBLE, MPI_MAX, comm);
  MPI_Allreduce(MPI_IN_PLACE, ghost.data(), int(ghost.size()), MPI_DOUBLE, MPI_MAX, comm);
  for (double s : secs) total += s;
  if (rank != 0) return;
  char line[256];
  std::snprintf(line, sizeof line, "%-32s %8s %12s %12s %7s\n", "step", "calls", "total [s]",
                "ghosts [s]", "share");
  out << line;
  for (std::size_t i = 0; i < m_timings.size(); ++i) {
    std::snprintf(line, sizeof line, "%-32s %8ld %12.4f %12.4f %6.1f%%\n",
                  m_timings[i].name.c_str(), m_timings[i].calls, secs[i], ghost[i],
                  total > 0 ? 100.0 * secs[i] / total : 0.0);
    out << line;
  }
  std::snprintf(line, sizeof line, "%-32s %8s %12.4f\n", "all steps", "", total);
  out << line;
}

}  // namespace mpmice
