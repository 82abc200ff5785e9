#pragma once
// set_args(kernel, a, b, c) = kernel.setArg(0, a); kernel.setArg(1, b); ... for the occlusion
// stages, whose kernels take many arguments.
#include <CL/opencl.hpp>

#include <utility>

namespace probeless::occlusion {

template <typename... Args>
void set_args(::cl::Kernel& kernel, Args&&... args) {
  cl_uint index = 0;
  (kernel.setArg(index++, std::forward<Args>(args)), ...);
}

}  // namespace probeless::occlusion
