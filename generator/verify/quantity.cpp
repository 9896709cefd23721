#include <mollify/error.hpp>
#include <mollify/verify.hpp>

#include <array>
#include <string>

namespace mollify::verify {

namespace {

struct Named {
    std::string_view name;
    Quantity quantity;
};
// "dpotential" is mollify's name of dphi/dr (table.hpp), "force" the issue's.
constexpr std::array<Named, 6> names{{{"value", Quantity::value},
                                      {"dr", Quantity::dr},
                                      {"potential", Quantity::potential},
                                      {"force", Quantity::force},
                                      {"grad_over_r", Quantity::grad_over_r},
                                      {"dpotential", Quantity::force}}};

}  // namespace

std::string_view name(Quantity q) {
    for (const Named& n : names)
        if (n.quantity == q) return n.name;
    fail("unknown verify::Quantity " + std::to_string(static_cast<int>(q)));
}

Quantity parse_quantity(std::string_view text) {
    std::string known;
    for (const Named& n : names) {
        if (n.name == text) return n.quantity;
        known += (known.empty() ? "" : ", ") + std::string(n.name);
    }
    fail("unknown quantity '" + std::string(text) + "' (known: " + known + ")");
}

std::string_view name(DiagnosisKind kind) {
    switch (kind) {
        case DiagnosisKind::constant_factor: return "constant factor";
        case DiagnosisKind::support_convention: return "support convention";
        case DiagnosisKind::gradient_factor: return "gradient factor";
        case DiagnosisKind::wrong_sign: return "wrong sign";
        case DiagnosisKind::other_dimension: return "other dimension";
        case DiagnosisKind::edge_cancellation: return "cancellation near the edge";
        case DiagnosisKind::single_precision: return "single precision";
        case DiagnosisKind::not_finite: return "not finite";
        case DiagnosisKind::unexplained: return "unexplained";
    }
    fail("unknown verify::DiagnosisKind " + std::to_string(static_cast<int>(kind)));
}

}  // namespace mollify::verify
