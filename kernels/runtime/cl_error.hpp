#pragma once
#include <CL/cl.h>

namespace probeless::cl {
// The symbolic name of an OpenCL error code ("CL_OUT_OF_RESOURCES"), for messages.
const char* error_name(cl_int code);
}  // namespace probeless::cl
