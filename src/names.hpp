// Internal: the one mechanism behind every public enum's names (to_string and parse_*, used as
// they are by the C ABI, the Python module and the CLI): a table of (value, name) entries per
// enum, in src/names.cpp. The first entry of a value is its name; later ones are accepted
// spellings. One behaviour everywhere: an unknown value prints "unknown"; parsing a null or
// unknown name returns false and writes nothing; a null `out` only asks whether the name is known.
#pragma once

#include <cstddef>
#include <cstring>

namespace reproject {
namespace detail {

template <class E>
struct EnumName {
  E value;
  const char* name;
};

template <class E, std::size_t N>
const char* name_of(const EnumName<E> (&table)[N], E value) noexcept {
  for (const EnumName<E>& entry : table)
    if (entry.value == value) return entry.name;
  return "unknown";
}

template <class E, std::size_t N>
bool parse_name(const EnumName<E> (&table)[N], const char* name, E* out) noexcept {
  if (name == nullptr) return false;
  for (const EnumName<E>& entry : table) {
    if (std::strcmp(name, entry.name) == 0) {
      if (out != nullptr) *out = entry.value;
      return true;
    }
  }
  return false;
}

}  // namespace detail
}  // namespace reproject
