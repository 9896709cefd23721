// libFuzzer harness: the samples CSV reader of `mollify verify --samples`
// (tools/mollify/samples_csv.cpp). Any text is a table or a mollify::Error;
// a table has three columns of equal length, finite, r >= 0, h > 0.
#include "samples_csv.hpp"

#include <mollify/error.hpp>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        const auto t = mollify::app::parse_samples_csv(text, "fuzz.csv");
        if (t.r.empty() || t.h.size() != t.r.size() || t.value.size() != t.r.size()) std::abort();
        for (std::size_t i = 0; i < t.r.size(); ++i)
            if (!(t.r[i] >= 0) || !(t.h[i] > 0) || !std::isfinite(t.r[i]) || !std::isfinite(t.h[i]) ||
                !std::isfinite(t.value[i]))
                std::abort();
    } catch (const mollify::Error&) {
    }
    return 0;
}
