// The exact world uses mollify's one error type (include/mollify/error.hpp);
// the CLI maps it to exit status 2.
#pragma once

#include <mollify/error.hpp>

namespace mollify::gen {

using mollify::Error;
using mollify::fail;

}  // namespace mollify::gen
