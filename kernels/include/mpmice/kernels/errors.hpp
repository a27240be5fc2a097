#pragma once
/// \file errors.hpp
/// \brief Exceptions thrown by host code. Device code only uses KOKKOS_ASSERT.
#include <stdexcept>
#include <string>

namespace mpmice {

/// Bad input or configuration: the mini-app reports it and exits with status 2.
/// `key` names what is wrong (an input key path, an option), `line` its line (0 if
/// unknown).
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& key, const std::string& what, int line = 0)
      : std::runtime_error(what), m_key(key), m_line(line) {}
  const std::string& key() const { return m_key; }
  int line() const { return m_line; }

 private:
  std::string m_key;
  int m_line;
};

/// A broken invariant during a run (non-finite state, negative mass, ...): the
/// mini-app reports the step, cell and material, and exits with status 3.
class InvariantError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace mpmice
