// Numbers in error messages: the shortest decimal that reads back as x.
#pragma once

#include <charconv>
#include <string>

namespace mollify::detail {

// 0.6, not 0.59999999999999998.
inline std::string show(double x) {
    char buf[32];
    return {buf, std::to_chars(buf, buf + sizeof buf, x).ptr};
}

}  // namespace mollify::detail
