// What the Fortran-speaking writers share (write_fortran.cpp defines it;
// write_phantom.cpp uses it): the exact spelling of a double, the
// Precision::fast helpers as module procedures, and the Syntax of
// target_code.hpp for Fortran.
#pragma once

#include "target_code.hpp"

#include <string>
#include <vector>

namespace mollify::gen {

// real(z'<bits>', c_double): the double with exactly these bits (F2008 13.7.138).
std::string boz(double x);

// The evaluation helpers of mollify's Precision::fast form
// (include/mollify/detail/evaluate.hpp) as Fortran module procedures.
struct Helper {
    const char* name;
    std::vector<std::string> uses;  // helpers it calls (c_log1p: the interface to C's log1p)
    std::string code;
};
const std::vector<Helper>& fortran_helpers();

// The helpers `functions` calls, with those they call; `log1p`: whether
// C's log1p must be interfaced.
std::string used_helpers(const std::string& functions, bool& log1p);

// Piece bounds, edges and centres: the module's array b(0:), so that no line is long.
struct Literals {
    std::vector<double> values;
    std::string operator()(double x);
};

Syntax fortran_syntax(Literals& literals);

// A sum of terms over several lines, continued with '&'.
std::string continued(const std::string& text);

// A quantity's inside pieces as Fortran: an if/else if chain on q (a piece
// from its lower bound on), each assigning y; lines after `indent`, the
// assignments after `indent` + `inner`.
std::string fortran_piece_chain(const CodeQuantity& q, const Syntax& s, const std::string& indent, const std::string& inner);

}  // namespace mollify::gen
