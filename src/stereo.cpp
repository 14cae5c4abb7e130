// The stereo pipeline around reprojection (include/reproject/stereo.hpp): in progress.
#include "reproject/reproject.hpp"
