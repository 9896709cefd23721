// Precision's names, out of line: the message of an unknown one needs
// <string>, which precision.hpp (parsed by every StaticKernel unit) avoids.
#include <mollify/error.hpp>
#include <mollify/precision.hpp>

#include <string>

namespace mollify {

std::string_view name(Precision p) { return p == Precision::fast ? "fast" : "accurate"; }

Precision precision(std::string_view name) {
    if (name == "accurate") return Precision::accurate;
    if (name == "fast") return Precision::fast;
    fail("unknown precision '" + std::string(name) + "' (accurate or fast)");
}

}  // namespace mollify
