// What a test does under AddressSanitizer + UBSan at -O0 (CI's second
// build, MOLLIFY_SANITIZED_BUILD): every code path of the optimised build's
// run, not all of its workload. Emitting a missing Wendland function is by
// far the costliest step there (28 s CPU each at -O0 + ASan, every other
// family < 2 s: its Taylor pieces' bounds in MPFR), so the sanitized tests
// take one of them, wendland-missing:k=1 (its pieces have every basis the
// others have: S^j, arcsech, arcsin, log r, centred and edge series).
#pragma once

#include <string_view>

namespace mollify::testing {

#ifdef MOLLIFY_SANITIZED_BUILD
inline constexpr bool sanitized_build = true;
#else
inline constexpr bool sanitized_build = false;
#endif

// The missing Wendland functions a sanitized run leaves to the optimised one.
inline bool left_to_optimised_build(std::string_view spec) {
    return sanitized_build && spec.starts_with("wendland-missing:") && spec != "wendland-missing:k=1";
}

}  // namespace mollify::testing
