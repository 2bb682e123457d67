#pragma once
// InputError: bad input from a user (a material description, a command-line value, a
// data file). Its message is one line that names the place and the problem; the CLI
// prints it and exits with status 2.

#include <stdexcept>
#include <string>

namespace gonio {

class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace gonio
