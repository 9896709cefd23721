// A function `double f(double r, double h)` from someone else's shared
// library (C, C++ extern "C", Fortran bind(C)), evaluated in a child process
// so that whatever it does (SIGSEGV, abort, an exception escaping, exit, an
// endless loop) cannot take mollify down: the parent knows which argument the
// child was evaluating and names it (README, "Verify your kernel from any
// language").
//
// Protocol (fork + one pipe): the child dlopens the library, looks up the
// symbol, sends "ready", then one record per argument, in order, each as soon
// as it is computed; an error it can name (dlerror, an escaping exception)
// travels as a text record. The parent reads with a per-evaluation timeout,
// so the argument of the first missing record is the one that crashed or hung.
#pragma once

#include <chrono>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace mollify::app {

struct ForeignFunction {
    std::filesystem::path library;  // passed to dlopen as given (a name without '/' is searched for)
    std::string symbol;             // double symbol(double r, double h)
};

// Runs f at (r[i], h[i]) for every i in a child process and returns the
// values in order. A library dlopen cannot open (the dlerror text), a missing
// symbol, a crash (the signal and the argument), an evaluation taking longer
// than `timeout` (the argument), an exception escaping f or a call to exit,
// and a NaN or infinite result (the argument) are each a mollify::Error naming
// the symbol; the child is gone before the call returns or throws.
std::vector<double> evaluate_foreign(const ForeignFunction& f, std::span<const double> r, std::span<const double> h,
                                     std::chrono::milliseconds timeout = std::chrono::seconds(10));

}  // namespace mollify::app
