// libFuzzer harness for the command-line tool's argument parsing (tools/cli: Flags and the
// flags -> decoder / model / options setup of setup.cpp), without running a command: the input is
// an argument list (arguments separated by NUL bytes) for a `warp`-like command that declares every
// shared flag. Checked besides "no crash, no sanitizer report":
//  * parsing and every setup step either succeed or throw the tool's Failure, with a usage (2) or
//    runtime (1) code and a message; no other exception escapes (main() would report it as a
//    runtime error, not as the usage error it is);
//  * what the setup accepts, the library accepts: a decoder, model and options that passed the
//    flag checks validate, and a call with them on a small frame returns ok (docs/CLI.md: flags
//    are checked before any work, so a bad flag never reaches the library).
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "cli.hpp"
#include "reproject/reproject.hpp"

namespace {

using namespace reproject;
using namespace reproject::cli;

[[noreturn]] void fail_check(const char* what) {
  std::fprintf(stderr, "fuzz_cli: check failed: %s\n", what);
  std::abort();
}
#define CHECK(condition)                       \
  do {                                         \
    if (!(condition)) fail_check(#condition);  \
  } while (0)

// Runs one step; true when it returned, false when it threw the tool's Failure.
template <class F>
bool attempt(F step) {
  try {
    step();
    return true;
  } catch (const Failure& failure) {
    CHECK(failure.code == kExitUsage || failure.code == kExitRuntime);
    CHECK(!failure.message.empty());
    return false;
  } catch (...) {
    fail_check("an exception other than cli::Failure escaped the argument parsing");
  }
}

std::vector<Flags::Spec> all_specs() {
  std::vector<Flags::Spec> specs = source_flags();
  for (const auto& part : {camera_flags(true, true), option_flags(true, true, true)}) specs.insert(specs.end(), part.begin(), part.end());
  specs.push_back({"out", "FILE", "output"});
  specs.push_back({"methods", "LIST", "methods"});
  specs.push_back({"quiet", nullptr, "a switch"});
  return specs;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // The arguments: NUL-separated, at most 64 of them (argv never holds a NUL itself).
  std::vector<std::string> words(1);
  for (std::size_t i = 0; i < size && words.size() <= 64; ++i) {
    if (data[i] == 0) words.emplace_back();
    else words.back().push_back(static_cast<char>(data[i]));
  }
  std::vector<char*> argv;
  std::string program = "reproject", command = "warp";
  argv.push_back(program.data());
  argv.push_back(command.data());
  for (std::string& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  const int argc = static_cast<int>(argv.size()) - 1;

  Flags flags("warp", all_specs());
  if (!attempt([&] { flags.parse(argc, argv.data(), 2); })) return 0;
  CHECK(!flags.usage("reproject warp [flags]").empty());
  if (flags.help()) return 0;

  DepthDecoder decoder;
  ParallaxModel model;
  Options options;
  EyeDirection direction = EyeDirection::centre_to_right;
  const int width = 24;
  const bool have_decoder = attempt([&] { decoder = decoder_from_flags(flags); });
  const bool have_model = attempt([&] { model = model_from_flags(flags, width, &direction); });
  const bool have_options = attempt([&] { options = options_from_flags(flags, true); });
  attempt([&] { (void)arch_from_flags(flags); });
  attempt([&] { (void)flags.list("methods", "exact"); });
  attempt([&] { (void)flags.text("out", "x.png"); });
  if (have_decoder) CHECK(decoder.validate().ok());
  if (have_model) CHECK(model.validate().ok());

  // What passed the flag checks runs: a 24-pixel target (plus the guard band) of 2 rows.
  if (have_decoder && have_model && have_options && options.guard <= 64) {
    options.threads = 1;  // the flag's value is checked above; the pool size is no part of this
    const int source_width = width + 2 * options.guard;
    Image source(source_width, 2, 3);
    Image depth(source_width, 2, 1);
    Image target(width, 2, 3);
    CHECK(!source.empty() && !depth.empty() && !target.empty());
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < source_width; ++x) {
        const double z = 1.5 + (x % 5);
        depth.plane_data()[y * depth.stride() + x] =
            decoder.encoding() == DepthEncoding::disparity ? static_cast<float>(x % 5) : decoder.encode(z);
      }
    SourceView view{source.color(), depth.plane()};
    TargetView out;
    out.color = target.mutable_color();
    const Status status = reproject::reproject(view, decoder, model, options, out);
    if (!status.ok()) std::fprintf(stderr, "fuzz_cli: the library refused flags the tool accepted: %s\n", status.message());
    CHECK(status.ok());
  }
  return 0;
}
