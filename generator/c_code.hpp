// What the C-speaking writers share (write_c.cpp defines it; write_gadget4.cpp and write_swift.cpp
// use it): the Precision::fast helpers as static inline C functions
// (valid C99 and C++) and the Syntax of target_code.hpp for C, the
// coefficients read from the array <prefix>_c.
#pragma once

#include "target_code.hpp"

#include <string>

namespace mollify::gen {

extern const char* const c_helpers;
// mollify_c_ipow's (and its four-lane twin's) exponents: |n| < 256, else Error.
void check_c_power(int n);
Syntax c_syntax(const std::string& prefix);

// Exact values in C comments ("*/" never ends one early).
std::string comment_text(std::string s);

// A quantity's inside pieces as C: an if/else chain on q (a piece from its
// lower bound on), each assigning `target`; every line after `indent`.
std::string c_piece_chain(const CodeQuantity& q, const Syntax& s, const std::string& indent, const std::string& target);

// A function of q on [0, 1] (and outside: the exterior pieces, at r = q),
// `static inline double name(double q)`, with `meaning` as its comment
// (the GADGET-4 and SWIFT writers' functions of the unit-support variable).
std::string c_unit_function(const std::string& name, const std::string& meaning, const CodeQuantity& q, const Syntax& s);

}  // namespace mollify::gen
