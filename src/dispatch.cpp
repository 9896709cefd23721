// The choice of the evaluator's instruction set at load time: x86-64-v4
// (AVX-512: eight doubles a vector) where the CPU has it, else x86-64-v3
// (AVX2 + FMA: Precision::accurate's double-double products become one
// fused multiply-add each), else generic x86-64. A caller built with
// -march=native on an AVX-512 CPU gets AVX-512 StaticKernel loops; the
// run-time form keeps pace only with a copy of its own (kernel_bench on an
// AVX-512 machine: Wendland C4 W + grad W, accurate, 1.45-1.56x
// StaticKernel's time with the v3 copy, 1.00-1.05x with v4).
#include "evaluator.hpp"

#include <mollify/dynamic_kernel.hpp>

#include <array>
#include <atomic>
#include <cstdlib>
#include <string>

namespace mollify {
namespace detail {

// The copies of src/evaluator.cpp (CMake compiles it once per instruction set).
#if MOLLIFY_DISPATCH_X86
// One of these is this unit's own MOLLIFY_ISA, an inline namespace in the
// headers, reopened here without `inline` (valid C++, [namespace.def]; clang
// warns).
#if defined(__clang__)
#pragma clang diagnostic push
#pragma clang diagnostic ignored "-Winline-namespace-reopened-noninline"
#endif
namespace isa_generic {
extern const Evaluator isa_evaluator;
}
namespace isa_avx2_fma {
extern const Evaluator isa_evaluator;
}
#if MOLLIFY_DISPATCH_V4
namespace isa_avx512 {
extern const Evaluator isa_evaluator;
}
#endif
#if defined(__clang__)
#pragma clang diagnostic pop
#endif
#else
inline namespace MOLLIFY_ISA {
extern const Evaluator isa_evaluator;
}
#endif

namespace {

struct Choice {
    const char* name;
    const Evaluator* evaluator;
    bool supported;
};

// Best first.
std::array<Choice, 3> choices() {
#if MOLLIFY_DISPATCH_X86
    __builtin_cpu_init();
    const bool v3 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#if MOLLIFY_DISPATCH_V4  // not in the sanitizer build (CMakeLists.txt)
    const bool v4 = v3 && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
                    __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl");
    const Evaluator* avx512 = &isa_avx512::isa_evaluator;
#else
    const bool v4 = false;
    const Evaluator* avx512 = &isa_avx2_fma::isa_evaluator;
#endif
    return {{{"x86-64-v4", avx512, v4},
             {"x86-64-v3", &isa_avx2_fma::isa_evaluator, v3},
             {"generic", &isa_generic::isa_evaluator, true}}};
#else
    return {{{"generic", &isa_evaluator, true}, {"generic", &isa_evaluator, true}, {"generic", &isa_evaluator, true}}};
#endif
}

const std::array<Choice, 3>& all_choices() {
    static const std::array<Choice, 3> all = choices();
    return all;
}

const Choice& find(std::string_view name) {
    for (const Choice& c : all_choices())
        if (name == c.name) {
            if (!c.supported)
                fail("instruction set " + std::string(name) + " is not supported by this CPU (or not built into this library)");
            return c;
        }
    fail("unknown instruction set '" + std::string(name) + "' (x86-64-v4, x86-64-v3 or generic)");
}

const Choice& best() {
    for (const Choice& c : all_choices())
        if (c.supported) return c;
    return find("generic");
}

std::atomic<const Choice*>& current() {
    static std::atomic<const Choice*> chosen = [] {
        const char* forced = std::getenv("MOLLIFY_ISA");
        return forced && *forced ? &find(forced) : &best();
    }();
    return chosen;
}

}  // namespace

const Evaluator& evaluator() { return *current().load(std::memory_order_relaxed)->evaluator; }

}  // namespace detail

std::string_view isa() { return detail::current().load()->name; }
void use_isa(std::string_view name) { detail::current().store(&detail::find(name)); }

}  // namespace mollify
