// The exceptions mbao throws. Bad arguments are std::invalid_argument (Python:
// ValueError); everything else derives from mbao::Error (Python: mbao.Error).
#pragma once

#include <stdexcept>
#include <string>

namespace mbao {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A scene or camera file that cannot be read or does not hold what it must.
class LoadError : public Error {
 public:
  using Error::Error;
};

// Anything OpenCL reports: no device, a failed build, a failed launch.
class DeviceError : public Error {
 public:
  using Error::Error;
};

}  // namespace mbao
