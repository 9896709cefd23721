#include "write_cpp.hpp"

#include "emit_checks.hpp"
#include "emit_plan.hpp"
#include "rounding.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>

namespace mollify::gen {

namespace {

class HeaderWriter {
public:
    explicit HeaderWriter(std::string id) : id_(std::move(id)) {}

    // Returns the C++ expression of the Quantity.
    // `parts`: for a combination, its terms' quantities w_j f_j (else empty).
    std::string quantity(const std::string& name, const Radial* f, bool potential_like,
                         const std::vector<Radial>& parts) {
        if (!f) return "{.pieces = nullptr, .npieces = 0}";
        std::vector<std::string> pieces;
        const std::vector<EmittedPiece> emitted = plan_quantity(*f, potential_like, parts);
        check_emitted(*f, emitted);
        for (std::size_t i = 0; i < emitted.size(); ++i) {
            const auto& [lo, hi, terms, note, series, centred] = emitted[i];
            const std::string terms_name = name + "_" + std::to_string(i);
            const std::string hi_text = hi ? hex_literal(round_to_double(*hi)) : "table::infinity";
            std::vector<std::string> term_exprs;
            if (centred) term_exprs.push_back(centred_term(terms_name + "_0", *centred, hi_text));
            for (std::size_t t = 0; t < terms.size(); ++t) {
                const std::string cname = terms_name + "_" + std::to_string(t);
                const auto& term = terms[t];
                std::vector<double> c, c_lo;
                std::vector<std::string> exact;
                for (const Exact& x : term.c) {
                    c.push_back(round_to_double(x));
                    c_lo.push_back(low_part(x, c.back()));
                    exact.push_back(x.to_string());
                }
                const std::string lo_name = coefficients(cname, c, c_lo, exact);
                if (term.centre) {
                    const double centre = round_to_double(*term.centre);
                    term_exprs.push_back(term_text("one", 0, "shifted", hi_text, 0, term.low, cname, term.c.size(),
                                                   centre, low_part(*term.centre, centre), lo_name, 0.0));
                    continue;
                }
                const std::optional<Q> edge = term.edge ? term.edge : hi;
                const double edge_hi = edge ? round_to_double(*edge) : 0;
                term_exprs.push_back(term_text(table::basis_name(term.basis), term.s_power, term.square ? "r2" : "r",
                                               edge ? hex_literal(edge_hi) : hi_text, term.edge_power, term.low, cname,
                                               term.c.size(), 0.0, 0.0, lo_name,
                                               edge ? low_part(*edge, edge_hi) : 0.0));
            }
            std::string terms_ref = "nullptr";
            if (!term_exprs.empty()) {
                body_ += "inline constexpr table::Term " + terms_name + "[] = {\n";
                for (const auto& e : term_exprs) body_ += "    " + e + ",\n";
                body_ += "};\n";
                terms_ref = terms_name;
            }
            pieces.push_back("{.lo = " + hex_literal(round_to_double(lo)) + ", .hi = " + hi_text + ", .terms = " +
                             terms_ref + ", .nterms = " + std::to_string(term_exprs.size()) + "},  // [" +
                             short_string(lo) + ", " +
                             (hi ? short_string(*hi) : std::string("inf")) + ")" + (note.empty() ? "" : ", " + note));
        }
        body_ += "inline constexpr table::Piece " + name + "[] = {\n";
        for (const auto& p : pieces) body_ += "    " + p + "\n";
        body_ += "};\n";
        return "{.pieces = detail_" + id_ + "::" + name + ", .npieces = " + std::to_string(pieces.size()) + "}";
    }

    std::string body() const { return body_; }

private:
    // The one term of a Taylor piece: sum_k a_k v^k, v = r - centre
    // (table::Var::shifted), the centre as a double and its rounding error.
    std::string centred_term(const std::string& cname, const CentredPiece& p, const std::string& hi_text) {
        const std::vector<double> a = rounded(p);
        std::vector<double> a_lo;
        std::vector<std::string> exact;
        for (std::size_t k = 0; k < a.size(); ++k) {
            a_lo.push_back(centred_low_part(p, k, a[k]));
            exact.push_back(p.a[k].to_string(p.centre));
        }
        const std::string lo_name = coefficients(cname, a, a_lo, exact);
        const double centre = round_to_double(p.centre), centre_lo = low_part(p.centre, centre);
        return term_text(p.s_power ? "sqrt_power" : "one", p.s_power, "shifted", hi_text, 0, p.low, cname, a.size(),
                         centre, centre_lo, lo_name, 0.0);
    }

    // A table::Term initialiser, its members named in declaration order;
    // the defaulted ones (centre, centre_lo, c_lo, edge_lo) are written only
    // where they differ from their default, a +0.0 double or nullptr.
    static std::string term_text(const std::string& basis, int s_power, const std::string& var,
                                 const std::string& edge, int edge_power, int low, const std::string& c, std::size_t n,
                                 double centre, double centre_lo, const std::string& c_lo, double edge_lo) {
        auto optional = [](const char* member, double x) {
            return std::signbit(x) || x != 0 ? std::string(", .") + member + " = " + hex_literal(x) : std::string();
        };
        return "{.basis = table::Basis::" + basis + ", .s_power = " + std::to_string(s_power) +
               ", .var = table::Var::" + var + ", .edge = " + edge + ", .edge_power = " + std::to_string(edge_power) +
               ", .low = " + std::to_string(low) + ", .c = " + c + ", .n = " + std::to_string(n) +
               optional("centre", centre) + optional("centre_lo", centre_lo) +
               (c_lo == "nullptr" ? std::string() : ", .c_lo = " + c_lo) + optional("edge_lo", edge_lo) + "}";
    }

    // A term's coefficients (correctly rounded, the exact value beside each)
    // and their low parts c - round(c), correctly rounded: the double-double
    // coefficients of Precision::accurate (table::Term::c_lo).
    // Returns the name of the low parts' array, "nullptr" where c is exact.
    std::string coefficients(const std::string& name, const std::vector<double>& c, const std::vector<double>& c_lo,
                             const std::vector<std::string>& exact) {
        body_ += "inline constexpr double " + name + "[] = {\n";
        for (std::size_t k = 0; k < c.size(); ++k) body_ += "    " + hex_literal(c[k]) + ",  // " + exact[k] + "\n";
        body_ += "};\n";
        if (std::all_of(c_lo.begin(), c_lo.end(), [](double x) { return x == 0; })) return "nullptr";
        body_ += "inline constexpr double " + name + "_lo[] = {";
        for (std::size_t k = 0; k < c_lo.size(); ++k)
            body_ += std::string(k % 4 == 0 ? "\n    " : " ") + hex_literal(c_lo[k]) + ",";
        body_ += "\n};\n";
        return name + "_lo";
    }

    std::string id_;
    std::string body_;
};

// `text` with every character but letters and digits written '_'.
std::string sanitized(const std::string& text) {
    std::string out;
    for (char c : text) out += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
    return out;
}

}  // namespace

std::string kernel_cpp(const KernelFacts& f) {
    const ExactKernel& k = f.kernel;
    HeaderWriter w(f.id);
    std::vector<std::string> quantities;
    for (int i = 0; i < table::quantity_count; ++i)
        quantities.push_back(w.quantity(table::quantity_names[i], quantity_of(f, i),
                                        table::is_potential(static_cast<table::QuantityId>(i)), parts_of(f, i)));
    std::ostringstream cpp;
    cpp << "\n// " << f.spec << " in D = " << k.dim << ": " << k.source << "\n";
    cpp << "namespace detail_" << f.id << " {\n" << w.body() << "}  // namespace detail_" << f.id << "\n";
    cpp << "inline constexpr table::Kernel " << f.id << " = {\n";
    cpp << "    .spec = \"" << f.spec << "\",\n    .dim = " << k.dim << ",\n    .support = 0x1p+0,\n";
    cpp << "    .smoothness = " << k.claims.smoothness << ",\n    .order = " << k.claims.order
        << ",\n    .parity = " << k.W.parity << ",\n";
    cpp << "    .normalisation = " << hex_literal(round_to_double(k.normalisation)) << ",  // "
        << k.normalisation.to_string() << "\n";
    cpp << "    .normalisation_exact = \"" << k.normalisation.to_string() << "\",\n";
    cpp << "    .has_potential = " << (k.claims.no_potential.empty() ? "true" : "false") << ",\n";
    cpp << "    .quantities = {\n";
    for (std::size_t i = 0; i < quantities.size(); ++i)
        cpp << "        " << quantities[i] << ",  // " << table::quantity_names[i] << "\n";
    cpp << "    }};\n";
    return cpp.str();
}

// The header of one kernel in one dimension, relative to generated/:
// mollify/tables/<family>/<parameters>_D<dim>.hpp, the family and the
// parameters being the two sides of the canonical spec's first ':' with
// every character but letters and digits written '_'
// (wendland:k=2,l=1 -> wendland/k_2_l_1_D3.hpp, wendland-missing:k=1 ->
// wendland_missing/k_1_D3.hpp, combo:m=3,base=wendland:k=2 ->
// combo/m_3_base_wendland_k_2_D3.hpp); a kernel without parameters
// (poly6, box-d1) goes to classic/<name>_D<dim>.hpp. Its symbol,
// identifier(spec, dim), is <family>_<parameters>_D<dim> (or
// <name>_D<dim>), so two kernels share a path only if they share a symbol.
std::string kernel_header(const std::string& spec, int dim) {
    const std::size_t colon = spec.find(':');
    const std::string family = colon == std::string::npos ? "classic" : spec.substr(0, colon);
    const std::string rest = colon == std::string::npos ? spec : spec.substr(colon + 1);
    return "mollify/tables/" + sanitized(family) + "/" + identifier(rest, dim) + ".hpp";
}

std::string kernel_file(const std::string& command, const std::string& text) {
    return banner(command, "//") +
           "// Each coefficient is correctly rounded, its exact value beside it; NAME_lo[k] is\n"
           "// the rounding error (exact - NAME[k]), correctly rounded (table.hpp: Term::c_lo).\n"
           "#pragma once\n\n#include <mollify/table.hpp>\n\nnamespace mollify::tables {\n" +
           text + "\n}  // namespace mollify::tables\n";
}

// The list of every emitted kernel, declared without any table: a program
// that iterates it links the compiled generated/src/catalogue.cpp (the
// mollify library) instead of compiling every table itself.
std::string catalogue_header(const std::string& command) {
    return banner(command, "//") +
           "#pragma once\n\n#include <mollify/table.hpp>\n\n#include <span>\n\nnamespace mollify::tables {\n\n"
           "// Every emitted kernel, in catalogue order (generated/src/catalogue.cpp).\n"
           "extern const std::span<const table::Kernel* const> all_kernels;\n\n}  // namespace mollify::tables\n";
}

std::string catalogue_source(const std::string& command, const std::vector<std::string>& headers,
                             const std::vector<std::string>& ids) {
    std::string out = banner(command, "//") + "#include <mollify/tables/catalogue.hpp>\n\n";
    for (const std::string& h : headers) out += "#include <" + h + ">\n";
    out += "\nnamespace mollify::tables {\n\nnamespace {\n\nconstexpr const table::Kernel* kernels[] = {\n";
    for (const std::string& id : ids) out += "    &" + id + ",\n";
    out += "};\n\n}  // namespace\n\n"
           "constinit const std::span<const table::Kernel* const> all_kernels{kernels};\n\n"
           "}  // namespace mollify::tables\n";
    return out;
}

}  // namespace mollify::gen
