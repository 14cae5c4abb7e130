// reproject: the command-line front end of the library (docs/CLI.md).
//
//   reproject warp     colour + depth files -> one target eye
//   reproject pair     a centre view -> both eyes, as files and stereo pictures
//   reproject compare  every method on a frame or a built-in scene: speed and quality table
//   reproject scene    a built-in scene's views (colour, depth, true eyes) as files
//   reproject budget   a depth buffer's parallax budget: figures, comfort shares, histogram picture
#include <cstdio>
#include <cstring>
#include <new>
#include <string>
#include <vector>

#include "cli.hpp"
#include "imageio/os.hpp"

namespace {

const char kUsage[] =
    "usage: reproject <command> [flags]    (reproject <command> --help for its flags)\n"
    "       reproject --version\n"
    "\n"
    "commands:\n"
    "  warp     synthesise one eye from a colour + depth (or disparity) image\n"
    "  pair     synthesise both eyes from a centre view; separate files and/or stereo pictures\n"
    "  compare  run every method on a frame or a built-in scene: speed, agreement with exact,\n"
    "           error against the true other eye\n"
    "  scene    write a built-in scene's views (colour, depth, true eyes) to files\n"
    "  budget   parallax budget of a depth file or a built-in scene: min/max, percentiles, comfort\n"
    "           shares, histogram picture\n"
    "\n"
    "exit codes: 0 ok, 1 runtime error, 2 usage error, 3 input file error, 4 output file error\n";

}  // namespace

int main(int argc, char** system_argv) {
  using namespace reproject::cli;
  // UTF-8 arguments on every system (Windows passes the ANSI code page's bytes).
  std::vector<std::string> arguments = reproject::io::os::arguments(argc, system_argv);
  std::vector<char*> argv_utf8;
  for (std::string& argument : arguments) argv_utf8.push_back(argument.data());
  argv_utf8.push_back(nullptr);
  argc = static_cast<int>(arguments.size());
  char** argv = argv_utf8.data();
  if (argc < 2) {
    std::fputs(kUsage, stderr);
    return kExitUsage;
  }
  const std::string command = argv[1];
  remove_temporaries_on_signals();
  // A command that fails after Ctrl-C was interrupted, whatever step failed (Windows: once the
  // console handler has removed the temporary files, a write under way fails).
  auto failed = [](int code) { return interruption()->load() ? static_cast<int>(kExitInterrupted) : code; };
  try {
    // Before the environment check: the version is printed whatever the environment says.
    if (command == "--version") {
      if (argc > 2) fail(kExitUsage, "--version takes no arguments");
      std::printf("reproject %s\n", reproject::version());
      return kExitOk;
    }
    check_environment();
    if (command == "warp") return run_warp(argc, argv);
    if (command == "pair") return run_pair(argc, argv);
    if (command == "compare") return run_compare(argc, argv);
    if (command == "scene") return run_scene(argc, argv);
    if (command == "budget") return run_budget(argc, argv);
    if (command == "help" || command == "--help" || command == "-h") {
      std::fputs(kUsage, stdout);
      return kExitOk;
    }
    std::fprintf(stderr, "reproject: error: unknown command '%s' (warp, pair, compare, scene, budget; see reproject --help)\n",
                 command.c_str());
    return kExitUsage;
  } catch (const Failure& f) {
    // Outputs are flushed first so that the error is the last line a user sees.
    std::fflush(stdout);
    std::fprintf(stderr, "reproject: error: %s\n", f.message.c_str());
    return failed(f.code);
  } catch (const std::bad_alloc&) {
    std::fflush(stdout);
    std::fprintf(stderr, "reproject: error: out of memory\n");
    return failed(kExitRuntime);
  } catch (const std::exception& e) {
    std::fflush(stdout);
    std::fprintf(stderr, "reproject: error: %s\n", e.what());
    return failed(kExitRuntime);
  }
}
