// mollify's double-precision runtime, the one header users include:
// kernels chosen at compile time (StaticKernel<table>) or at run time from a
// spec string (kernel(spec, dim)), with their gradients, Hessians,
// Laplacians and potentials, every number from the exact generator's tables.
#pragma once

#include <mollify/dynamic_kernel.hpp>
#include <mollify/error.hpp>
#include <mollify/smoothing.hpp>
#include <mollify/spec.hpp>
#include <mollify/static_kernel.hpp>
