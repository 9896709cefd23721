// Compiled (syntax only) with -ffast-math by the test StaticKernel.AccurateRefusesFastMath
// (tests/CMakeLists.txt), which passes only where the compiler prints
// StaticKernel's refusal: Precision::accurate's error-free transformations
// would be reassociated away there. Precision::fast compiles.
#include <mollify/static_kernel.hpp>
#include <mollify/tables/wendland/k_2_D3.hpp>

using Fast = mollify::StaticKernel<mollify::tables::wendland_k_2_D3, mollify::Precision::fast>;
using Accurate = mollify::StaticKernel<mollify::tables::wendland_k_2_D3>;

double fast(double r, const mollify::Smoothing& s) { return Fast::radial<mollify::QuantityId::value>(r, s); }
double accurate(double r, const mollify::Smoothing& s) { return Accurate::radial<mollify::QuantityId::value>(r, s); }
