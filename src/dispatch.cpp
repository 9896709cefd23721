// The choice of the evaluator's instruction set at load time: x86-64-v3
// (AVX2 + FMA: Precision::accurate's double-double products become one
// fused multiply-add each) where the CPU has it, else generic x86-64.
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
namespace isa_generic {
extern const Evaluator isa_evaluator;
}
namespace isa_avx2_fma {
extern const Evaluator isa_evaluator;
}
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

std::array<Choice, 2> choices() {
#if MOLLIFY_DISPATCH_X86
    __builtin_cpu_init();
    const bool v3 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    return {{{"x86-64-v3", &isa_avx2_fma::isa_evaluator, v3}, {"generic", &isa_generic::isa_evaluator, true}}};
#else
    return {{{"generic", &isa_evaluator, true}, {"generic", &isa_evaluator, true}}};
#endif
}

const Choice& find(std::string_view name) {
    static const std::array<Choice, 2> all = choices();
    for (const Choice& c : all)
        if (name == c.name) {
            if (!c.supported) fail("instruction set " + std::string(name) + " is not supported by this CPU");
            return c;
        }
    fail("unknown instruction set '" + std::string(name) + "' (x86-64-v3 or generic)");
}

const Choice& best() {
    static const std::array<Choice, 2> all = choices();
    return all[0].supported ? find(all[0].name) : find(all[1].name);
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
