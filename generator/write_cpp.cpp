#include "write_cpp.hpp"

#include "rounding.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string_view>

namespace mollify::gen {

namespace {

// Appends the parts to `out` (no temporary strings: a missing Wendland
// kernel's header is ~1 MB of coefficients and their exact values).
void append(std::string& out, std::initializer_list<std::string_view> parts) {
    for (std::string_view p : parts) out += p;
}

// A table::Term initialiser's doubles: table::infinity by name.
std::string double_text(double x) { return std::isinf(x) ? "table::infinity" : hex_literal(x); }

// The header's size, near enough to reserve it once: a coefficient's line is
// its hex-float and its exact value, a low part ~25 characters.
std::size_t estimated_size(const std::vector<std::optional<std::vector<RoundedPiece>>>& tables) {
    std::size_t size = 4096;
    for (const auto& q : tables)
        if (q)
            for (const RoundedPiece& p : *q) {
                size += 200 + p.note.size();
                for (const RoundedTerm& t : p.terms) {
                    size += 400 + 25 * t.c_lo.size();
                    for (const std::string& e : t.exact) size += 40 + e.size();
                }
            }
    return size;
}

class HeaderWriter {
public:
    HeaderWriter(std::string id, std::string& out) : id_(std::move(id)), body_(out) {}

    // Writes a quantity's arrays; returns the C++ expression of its table::Quantity.
    std::string quantity(const std::string& name, const std::optional<std::vector<RoundedPiece>>& q) {
        if (!q) return "{.pieces = nullptr, .npieces = 0}";
        std::vector<std::string> pieces;
        for (std::size_t i = 0; i < q->size(); ++i) {
            const RoundedPiece& p = (*q)[i];
            const std::string terms_name = name + "_" + std::to_string(i);
            std::vector<std::string> term_exprs;
            for (std::size_t t = 0; t < p.terms.size(); ++t)
                term_exprs.push_back(term(terms_name + "_" + std::to_string(t), p.terms[t]));
            std::string terms_ref = "nullptr";
            if (!term_exprs.empty()) {
                append(body_, {"inline constexpr table::Term ", terms_name, "[] = {\n"});
                for (const auto& e : term_exprs) append(body_, {"    ", e, ",\n"});
                body_ += "};\n";
                terms_ref = terms_name;
            }
            pieces.push_back("{.lo = " + hex_literal(p.lo) + ", .hi = " + double_text(p.hi) + ", .terms = " + terms_ref +
                             ", .nterms = " + std::to_string(term_exprs.size()) + "},  // " + p.note);
        }
        append(body_, {"inline constexpr table::Piece ", name, "[] = {\n"});
        for (const auto& p : pieces) append(body_, {"    ", p, "\n"});
        body_ += "};\n";
        return "{.pieces = detail_" + id_ + "::" + name + ", .npieces = " + std::to_string(pieces.size()) + "}";
    }

private:
    // A table::Term initialiser, its members named in declaration order;
    // the defaulted ones (centre, centre_lo, c_lo, edge_lo, plain) are written
    // only where they differ from their default, a +0.0 double, nullptr or 0.
    std::string term(const std::string& cname, const RoundedTerm& t) {
        const std::string c_lo = coefficients(cname, t);
        auto optional = [](const char* member, double x) {
            return std::signbit(x) || x != 0 ? std::string(", .") + member + " = " + hex_literal(x) : std::string();
        };
        return std::string("{.basis = table::Basis::") + table::basis_name(t.basis) +
               ", .s_power = " + std::to_string(t.s_power) + ", .var = table::Var::" + table::var_name(t.var) +
               ", .edge = " + double_text(t.edge) + ", .edge_power = " + std::to_string(t.edge_power) +
               ", .low = " + std::to_string(t.low) + ", .c = " + cname + ", .n = " + std::to_string(t.c.size()) +
               optional("centre", t.centre) + optional("centre_lo", t.centre_lo) +
               (c_lo == "nullptr" ? std::string() : ", .c_lo = " + c_lo) + optional("edge_lo", t.edge_lo) +
               (t.plain ? ", .plain = " + std::to_string(t.plain) : std::string()) + split(cname, t) + "}";
    }

    // table::Term::split and its integer coefficients m (c = content m).
    std::string split(const std::string& name, const RoundedTerm& t) {
        if (t.split == 0) return {};
        append(body_, {"// ", name, " = content * ", name, "_m, content = ", t.content_exact, " (table::Term::split)\n"});
        append(body_, {"inline constexpr double ", name, "_m[] = {\n"});
        for (double m : t.m) append(body_, {"    ", hex_literal(m), ",  // ", std::to_string(static_cast<long long>(m)), "\n"});
        body_ += "};\n";
        return ", .split = " + std::to_string(t.split) + ", .m = " + name + "_m, .content = " + hex_literal(t.content) +
               ", .content_lo = " + hex_literal(t.content_lo);
    }

    // A term's coefficients (correctly rounded, the exact value beside each)
    // and their low parts c - round(c), correctly rounded: the double-double
    // coefficients of Precision::accurate (table::Term::c_lo).
    // Returns the name of the low parts' array, "nullptr" where c is exact.
    std::string coefficients(const std::string& name, const RoundedTerm& t) {
        append(body_, {"inline constexpr double ", name, "[] = {\n"});
        for (std::size_t k = 0; k < t.c.size(); ++k) append(body_, {"    ", hex_literal(t.c[k]), ",  // ", t.exact[k], "\n"});
        body_ += "};\n";
        if (t.c_lo.empty()) return "nullptr";
        append(body_, {"inline constexpr double ", name, "_lo[] = {"});
        for (std::size_t k = 0; k < t.c_lo.size(); ++k) append(body_, {k % 4 == 0 ? "\n    " : " ", hex_literal(t.c_lo[k]), ","});
        body_ += "\n};\n";
        return name + "_lo";
    }

    std::string id_;
    std::string& body_;
};

}  // namespace

std::string kernel_file(const std::string& command, const KernelFacts& f,
                        const std::vector<std::optional<std::vector<RoundedPiece>>>& tables) {
    const ExactKernel& k = f.kernel;
    // One string, reserved once and written in order: every copy or
    // regrowth of ~1 MB is memory the emission touches again.
    std::string out;
    out.reserve(estimated_size(tables));
    append(out, {banner(command, "//"),
                 "// Each coefficient is correctly rounded, its exact value beside it; NAME_lo[k] is\n"
                 "// the rounding error (exact - NAME[k]), correctly rounded (table.hpp: Term::c_lo).\n"
                 "#pragma once\n\n#include <mollify/table.hpp>\n\nnamespace mollify::tables {\n"});
    append(out, {"\n// ", f.spec, " in D = ", std::to_string(k.dim), ": ", k.source, "\n"});
    append(out, {"namespace detail_", f.id, " {\n"});
    HeaderWriter w(f.id, out);
    std::vector<std::string> quantities;
    for (int i = 0; i < table::quantity_count; ++i)
        quantities.push_back(w.quantity(table::quantity_names[i], tables[static_cast<std::size_t>(i)]));
    std::ostringstream tail;
    tail << "}  // namespace detail_" << f.id << "\n";
    tail << "inline constexpr table::Kernel " << f.id << " = {\n";
    tail << "    .spec = \"" << f.spec << "\",\n    .dim = " << k.dim << ",\n    .support = 0x1p+0,\n";
    tail << "    .smoothness = " << k.claims.smoothness << ",\n    .order = " << k.claims.order
         << ",\n    .parity = " << k.W.parity << ",\n";
    tail << "    .normalisation = " << hex_literal(round_to_double(k.normalisation)) << ",  // "
         << k.normalisation.to_string() << "\n";
    tail << "    .normalisation_exact = \"" << k.normalisation.to_string() << "\",\n";
    tail << "    .has_potential = " << (k.claims.no_potential.empty() ? "true" : "false") << ",\n";
    tail << "    .quantities = {\n";
    for (std::size_t i = 0; i < quantities.size(); ++i)
        tail << "        " << quantities[i] << ",  // " << table::quantity_names[i] << "\n";
    tail << "    }};\n";
    append(out, {tail.str(), "\n}  // namespace mollify::tables\n"});
    return out;
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
