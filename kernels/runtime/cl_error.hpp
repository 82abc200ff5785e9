#pragma once
// OpenCL errors as the rest of probeless sees them: symbolic names for codes, and exceptions
// that carry their context (which call, which program, the compiler's log) so that the CLI
// can print them as they are.
#include <CL/opencl.hpp>
#include <stdexcept>
#include <string>

namespace probeless {

// The symbolic name of an OpenCL error code ("CL_OUT_OF_RESOURCES"), for messages.
const char* cl_error_name(cl_int code);

// "clEnqueueNDRangeKernel: CL_OUT_OF_RESOURCES (-5)" from what the C++ bindings throw.
std::string describe_cl_error(const ::cl::Error& e);

// A failure of the OpenCL runtime with its context; code() is the OpenCL error code.
class ClError : public std::runtime_error {
 public:
  ClError(const std::string& context, cl_int code);
  ClError(const std::string& context, const ::cl::Error& e) : ClError(context, e.err()) {}
  cl_int code() const { return code_; }

 private:
  cl_int code_;
};

// No platform or device matched the selector, or the ICD loader found no driver at all. The
// message lists what is available so that the user can correct the selector.
class DeviceSelectionError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A program failed to compile or link. what() includes the whole build log.
class ClBuildError : public std::runtime_error {
 public:
  ClBuildError(std::string program_name, std::string options, std::string log, cl_int code);
  const std::string& program_name() const { return program_name_; }
  const std::string& options() const { return options_; }
  const std::string& log() const { return log_; }
  cl_int code() const { return code_; }

 private:
  std::string program_name_;
  std::string options_;
  std::string log_;
  cl_int code_;
};

}  // namespace probeless
