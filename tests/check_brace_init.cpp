// Compiled, never run (reproject_brace_init_check, with -Wall -Wextra -Werror): code that brace-
// initialises the public views by their leading members, as code written before a member was
// added does, must build without warnings (GCC's -Wmissing-field-initializers skips members
// that have a default, so every member of SourceView and TargetView has one).
#include "reproject/reproject.hpp"

namespace {

[[maybe_unused]] reproject::Status warp(const reproject::ColorView& color, const reproject::FloatPlane& depth,
                                        const reproject::MutableColorView& out) {
  const reproject::SourceView source{color, depth};
  const reproject::TargetView target{out};
  return reproject::reproject(source, reproject::DepthDecoder{}, reproject::ParallaxModel{}, reproject::Options{},
                              target);
}

}  // namespace
