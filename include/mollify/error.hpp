// mollify's one error type, shared by the exact generator and the runtime:
// bad input (a kernel spec, a number, an option, a dimension) or a request
// the mathematics does not allow. The message names the offending value.
#pragma once

#include <stdexcept>
#include <string>

namespace mollify {

class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

[[noreturn]] inline void fail(const std::string& message) { throw Error(message); }

}  // namespace mollify
