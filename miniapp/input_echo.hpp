#pragma once
#include <string>

#include "input.hpp"

namespace mpmice {
/// The input with every default filled in, as YAML that load_input accepts.
std::string resolved_yaml(const Input& input);
}  // namespace mpmice
