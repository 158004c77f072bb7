// InputError: a problem in user-supplied input, with the file and line or field it comes from.
#pragma once

#include <stdexcept>
#include <string>

namespace planner_core {

class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace planner_core
