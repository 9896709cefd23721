// libFuzzer harness: the kernel-spec grammar (src/spec.cpp). Any text is
// either a Spec or a mollify::Error; a Spec's canonical spelling parses back
// to the same Spec (spec_string is the generator's table key), and numbers
// that split_number accepts either convert exactly or are an Error.
#include <mollify/spec.hpp>

#include <cstdint>
#include <cstdlib>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        const mollify::Spec spec = mollify::parse_spec(text);
        const std::string canonical = mollify::spec_string(spec);
        if (!(mollify::parse_spec(canonical) == spec)) std::abort();      // round trip
        if (mollify::spec_string(mollify::parse_spec(canonical)) != canonical) std::abort();
    } catch (const mollify::Error&) {
    }
    if (mollify::split_number(text)) {
        try {
            const mollify::Ratio q = mollify::parse_ratio(text, "fuzz");
            if (q.den <= 0) std::abort();
        } catch (const mollify::Error&) {
        }
    }
    return 0;
}
