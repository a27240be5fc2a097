#pragma once
// Reading a YAML input with every key checked: a Reader is one map node and the key
// path that leads to it. `get` reads a required key, `query` an optional one with a
// default; `finish` rejects keys nobody asked for. Every failure throws
// mpmice::InputError naming the key path and its line.
#include <yaml-cpp/yaml.h>

#include <array>
#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include <mpmice/kernels/errors.hpp>

namespace mpmice {

class Reader {
 public:
  Reader(const YAML::Node& node, std::string path) : m_node(node), m_path(std::move(path)) {
    // A missing or empty section reads as an empty map.
    if (m_node && !m_node.IsNull() && !m_node.IsMap()) fail("", "must be a map of keys");
  }

  const std::string& path() const { return m_path; }
  std::string key_path(const std::string& key) const { return m_path.empty() ? key : m_path + "." + key; }
  int line(const YAML::Node& n) const { return n.Mark().line >= 0 ? n.Mark().line + 1 : 0; }
  int line() const { return m_node ? line(m_node) : 0; }

  bool has(const std::string& key) {
    m_seen.insert(key);
    return is_map() && m_node[key];
  }
  YAML::Node node(const std::string& key) {
    m_seen.insert(key);
    return is_map() ? m_node[key] : YAML::Node();
  }
  Reader map(const std::string& key) {
    YAML::Node n = node(key);
    if (!n) fail(key, "is missing");
    return Reader(n, key_path(key));
  }

  template <class T>
  T get(const std::string& key) {
    YAML::Node n = node(key);
    if (!n || n.IsNull()) fail(key, "is missing");
    return convert<T>(n, key);
  }
  template <class T>
  T query(const std::string& key, const T& fallback) {
    YAML::Node n = node(key);
    if (!n || n.IsNull()) return fallback;
    return convert<T>(n, key);
  }

  /// A number with bounds; `open` excludes the lower bound.
  double number(const std::string& key, double lo, double hi, bool open_lo = false) {
    const double v = get<double>(key);
    check_range(key, v, lo, hi, open_lo);
    return v;
  }
  double number_or(const std::string& key, double fallback, double lo, double hi,
                   bool open_lo = false) {
    if (!has(key)) return fallback;
    return number(key, lo, hi, open_lo);
  }
  std::array<double, 3> vector3(const std::string& key) {
    auto v = get<std::vector<double>>(key);
    if (v.size() != 3) fail(key, "must have 3 entries [x, y, z]");
    return {v[0], v[1], v[2]};
  }
  std::array<double, 3> vector3_or(const std::string& key, std::array<double, 3> fallback) {
    return has(key) ? vector3(key) : fallback;
  }
  std::string choice(const std::string& key, const std::vector<std::string>& allowed,
                     const std::string& fallback = "") {
    std::string v = fallback.empty() ? get<std::string>(key) : query<std::string>(key, fallback);
    for (const auto& a : allowed)
      if (a == v) return v;
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
    fail(key, "is '" + v + "' (allowed: " + list + ")");
    return v;
  }

  /// A list of names, each one of `allowed`.
  std::vector<std::string> names(const std::string& key, const std::vector<std::string>& allowed) {
    auto values = get<std::vector<std::string>>(key);
    for (const auto& v : values) {
      bool ok = false;
      for (const auto& a : allowed) ok |= a == v;
      if (!ok) {
        std::string list;
        for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
        fail(key, "names '" + v + "' (allowed: " + list + ")");
      }
    }
    return values;
  }

  /// Reject keys that were not read.
  void finish() const {
    if (!is_map()) return;
    for (const auto& kv : m_node) {
      const std::string k = kv.first.as<std::string>();
      if (!m_seen.count(k))
        throw InputError(key_path(k), "unknown key '" + key_path(k) + "'", line(kv.first));
    }
  }

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    const std::string kp = key.empty() ? m_path : key_path(key);
    int ln = line();
    if (is_map() && !key.empty() && m_node[key]) ln = line(m_node[key]);
    throw InputError(kp, "'" + kp + "' " + what, ln);
  }
  void check_range(const std::string& key, double v, double lo, double hi, bool open_lo) const {
    if (!std::isfinite(v) || v < lo || v > hi || (open_lo && v == lo)) {
      std::string range = (open_lo ? "> " : ">= ") + fmt(lo);
      if (hi < std::numeric_limits<double>::max()) range += " and <= " + fmt(hi);
      fail(key, "is " + fmt(v) + ", but must be " + range);
    }
  }

 private:
  bool is_map() const { return m_node && m_node.IsMap(); }
  static std::string fmt(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%g", v);
    return b;
  }
  template <class T>
  T convert(const YAML::Node& n, const std::string& key) const {
    try {
      return n.as<T>();
    } catch (const YAML::Exception&) {
      fail(key, std::string("has the wrong type (expected ") + type_name<T>() + ")");
    }
  }
  template <class T>
  static const char* type_name() {
    if constexpr (std::is_same_v<T, double>) return "a number";
    else if constexpr (std::is_same_v<T, int> || std::is_same_v<T, long>) return "an integer";
    else if constexpr (std::is_same_v<T, bool>) return "true or false";
    else if constexpr (std::is_same_v<T, std::string>) return "a string";
    else if constexpr (std::is_same_v<T, std::vector<double>>) return "a list of numbers";
    else if constexpr (std::is_same_v<T, std::vector<int>>) return "a list of integers";
    else if constexpr (std::is_same_v<T, std::vector<bool>>) return "a list of true/false";
    else if constexpr (std::is_same_v<T, std::vector<std::string>>) return "a list of strings";
    else return "another type";
  }

  const YAML::Node m_node;  // const: a look-up never inserts a key
  std::string m_path;
  std::set<std::string> m_seen;
};

}  // namespace mpmice
