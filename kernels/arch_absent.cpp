// The table of an instruction set CMake does not compile for this processor (another family's,
// or any with REPROJECT_SIMD=OFF): compiled once per such set, with REPROJECT_ABSENT_TABLE naming
// its function (cmake/kernels.cmake), so that kernels/dispatch.cpp names every set alike.
#include "kernels/dispatch.hpp"

namespace reproject::detail {

const KernelTable* REPROJECT_ABSENT_TABLE() { return nullptr; }

}  // namespace reproject::detail
