// The one error type of mollify's exact world: bad input (a spec, a number,
// an option) or a request the mathematics does not allow. The message names
// the offending value; the CLI maps it to exit status 2.
#pragma once

#include <stdexcept>
#include <string>

namespace mollify::gen {

class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

[[noreturn]] inline void fail(const std::string& message) { throw Error(message); }

}  // namespace mollify::gen
