// SceneError: bad input. The command line prints it as one line and exits with code 2.
#pragma once

#include <stdexcept>
#include <string>

namespace vkrt {

class SceneError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

}  // namespace vkrt
