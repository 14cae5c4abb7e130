// The tool's own small flag parser (no dependency): names are checked against each subcommand's
// table, and values are converted and range-checked where they are read, so every message can
// name the flag and the value.
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "cli.hpp"

namespace reproject::cli {

void fail(int code, const std::string& message) { throw Failure{code, message}; }

bool is_decimal(const std::string& text, bool integer_only) {
  // strtod and strtol alone also take leading blanks, hexadecimal ("0x10"), "inf" and "nan".
  std::size_t i = 0;
  const std::size_t n = text.size();
  auto digits = [&] {
    const std::size_t start = i;
    while (i < n && text[i] >= '0' && text[i] <= '9') ++i;
    return i - start;
  };
  if (i < n && (text[i] == '+' || text[i] == '-')) ++i;
  std::size_t mantissa = digits();
  if (!integer_only && i < n && text[i] == '.') {
    ++i;
    mantissa += digits();
  }
  if (mantissa == 0) return false;
  if (!integer_only && i < n && (text[i] == 'e' || text[i] == 'E')) {
    ++i;
    if (i < n && (text[i] == '+' || text[i] == '-')) ++i;
    if (digits() == 0) return false;
  }
  return i == n;
}

const Flags::Spec* Flags::find(const std::string& name) const {
  for (const Spec& s : specs_) {
    if (name == s.name) return &s;
  }
  return nullptr;
}

void Flags::parse(int argc, char** argv, int first) {
  for (int i = first; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      help_ = true;
      continue;
    }
    if (arg.size() < 3 || arg.compare(0, 2, "--") != 0) {
      fail(kExitUsage, std::string("unexpected argument '") + arg + "' (flags start with --; see reproject " +
                           command_ + " --help)");
    }
    const std::size_t eq = arg.find('=');
    const std::string name = arg.substr(2, eq == std::string::npos ? std::string::npos : eq - 2);
    const Spec* spec = find(name);
    if (spec == nullptr) {
      fail(kExitUsage, "unknown flag '--" + name + "' for '" + command_ + "' (see reproject " + command_ + " --help)");
    }
    for (const auto& v : values_) {
      if (v.first == name) fail(kExitUsage, "--" + name + " is given more than once");
    }
    std::string value;
    if (spec->metavar == nullptr) {
      if (eq != std::string::npos) fail(kExitUsage, "--" + name + " is a switch and takes no value");
    } else if (eq != std::string::npos) {
      value = arg.substr(eq + 1);
    } else {
      // The next argument is the value whatever it looks like ("-5" is a number, not a flag);
      // only a missing one is an error.
      if (i + 1 >= argc) fail(kExitUsage, "--" + name + " needs a value (" + spec->metavar + ")");
      value = argv[++i];
    }
    if (spec->metavar != nullptr && value.empty()) fail(kExitUsage, "--" + name + " needs a value (" + spec->metavar + ")");
    values_.emplace_back(name, value);
  }
}

std::string Flags::usage(const char* synopsis) const {
  std::string out = std::string("usage: reproject ") + command_ + " " + synopsis + "\n\n";
  std::size_t widest = 0;
  for (const Spec& s : specs_) {
    widest = std::max(widest, std::strlen(s.name) + (s.metavar != nullptr ? std::strlen(s.metavar) + 1 : 0));
  }
  for (const Spec& s : specs_) {
    std::string left = std::string("  --") + s.name;
    if (s.metavar != nullptr) left += std::string(" ") + s.metavar;
    left.resize(widest + 6, ' ');
    out += left + s.help + "\n";
  }
  return out;
}

bool Flags::has(const char* name) const {
  for (const auto& v : values_) {
    if (v.first == name) return true;
  }
  return false;
}

std::string Flags::text(const char* name, const std::string& fallback) const {
  for (const auto& v : values_) {
    if (v.first == name) return v.second;
  }
  return fallback;
}

void Flags::bad_value(const char* name, const std::string& what) const {
  fail(kExitUsage, std::string("--") + name + ": " + what);
}

void Flags::forbid(const char* name, const std::string& why) const {
  if (has(name)) fail(kExitUsage, std::string("--") + name + " cannot be used with " + why);
}

void Flags::require(const char* name) const {
  if (has(name)) return;
  const Spec* spec = find(name);
  fail(kExitUsage, std::string(command_) + " needs --" + name +
                       (spec != nullptr && spec->metavar != nullptr ? std::string(" ") + spec->metavar : ""));
}

int Flags::integer(const char* name, int fallback, int min, int max) const {
  if (!has(name)) return fallback;
  const std::string v = text(name);
  char* end = nullptr;
  errno = 0;
  const long value = std::strtol(v.c_str(), &end, 10);
  if (!is_decimal(v, true) || end == v.c_str() || *end != '\0' || errno == ERANGE || value < min || value > max) {
    bad_value(name, "'" + v + "' is not an integer in " + std::to_string(min) + ".." + std::to_string(max));
  }
  return static_cast<int>(value);
}

double Flags::number(const char* name, double fallback) const {
  return number(name, fallback, -HUGE_VAL, HUGE_VAL);
}

double Flags::number(const char* name, double fallback, double min, double max, bool min_open) const {
  if (!has(name)) return fallback;
  const std::string v = text(name);
  char* end = nullptr;
  errno = 0;
  const double value = std::strtod(v.c_str(), &end);
  if (!is_decimal(v, false) || end == v.c_str() || *end != '\0' || !std::isfinite(value)) bad_value(name, "'" + v + "' is not a decimal number");
  if (value < min || value > max || (min_open && value == min)) {
    // %g: "0", "1e+09", "0.5" rather than std::to_string's six decimals.
    auto text_of = [](double x) {
      char t[32];
      std::snprintf(t, sizeof t, "%g", x);
      return std::string(t);
    };
    const std::string range = std::isinf(max) ? (min_open ? "greater than " : "at least ") + text_of(min)
                                               : "in " + text_of(min) + " .. " + text_of(max);
    bad_value(name, "'" + v + "' is not " + range);
  }
  return value;
}

std::vector<std::string> Flags::list(const char* name, const std::string& fallback) const {
  const std::string v = has(name) ? text(name) : fallback;
  std::vector<std::string> items;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = v.find(',', start);
    const std::string item = v.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    if (item.empty()) bad_value(name, "'" + v + "' has an empty item");
    items.push_back(item);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return items;
}

}  // namespace reproject::cli
