// The data writer: one compact text file per kernel and dimension holding
// everything its table::Kernel holds, for programs that load tables at run
// time (include/mollify/table_file.hpp) instead of compiling them.
//
// Format (version 4; version 3 had no checksum, version 2 no "split", version 1 no "plain"). Lines of fields separated by one space; every double
// is a C99 hex-float ("%a": exact, e.g. 0x1.3b2075224955ap+2, -0x0p+0, inf).
//   mollify-table 4
//   generator <the generator's version>    (the rest of the line)
//   spec <canonical spec>                  (the rest of the line)
//   dim <D>
//   support <double>
//   smoothness <int>
//   order <int>
//   parity <int>
//   normalisation <double>
//   normalisation_exact <exact value>      (the rest of the line)
//   has_potential <0|1>
// then the ten quantities in table::QuantityId order, each
//   quantity <name> <npieces>              (npieces 0: absent)
// followed by its pieces, each
//   piece <lo> <hi> <nterms>
// followed by its terms, one line each:
//   term <basis> <s_power> <var> <edge> <edge_lo> <edge_power> <low> <centre> <centre_lo> <n> <c_0> ... <c_n-1> <low parts>
// with <basis> a table::basis_name, <var> a table::var_name, and <low
// parts> either "-" (table::Term::c_lo = nullptr: the c_k are exact) or the
// n doubles c_lo_0 ... c_lo_n-1, then "plain <k>" where table::Term::plain
// is k > 0, then "split <s> <content> <content_lo> <m_0> ... <m_n-1>" where
// table::Term::split is s > 0; and last
//   end
//   checksum crc32 <8 lower-case hex digits>
// the CRC-32 (zlib's crc32, Python's zlib.crc32) of every byte before the
// checksum line, which the reader checks: a file changed after it was
// written fails to load (TableFile::version() >= 4).
#include "write_data.hpp"

#include <mollify/table_file.hpp>

#include "rounding.hpp"

#include <cstdio>

namespace mollify::gen {

namespace {

std::string hex(double x) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%a", x);
    return buf;
}

void write_term(std::string& out, const RoundedTerm& t) {
    out += std::string("term ") + table::basis_name(t.basis) + " " + std::to_string(t.s_power) + " " +
           table::var_name(t.var) + " " + hex(t.edge) + " " + hex(t.edge_lo) + " " + std::to_string(t.edge_power) + " " +
           std::to_string(t.low) + " " + hex(t.centre) + " " + hex(t.centre_lo) + " " + std::to_string(t.c.size());
    for (double c : t.c) out += " " + hex(c);
    if (t.c_lo.empty()) out += " -";
    for (double c : t.c_lo) out += " " + hex(c);
    if (t.plain) out += " plain " + std::to_string(t.plain);
    if (t.split) {
        out += " split " + std::to_string(t.split) + " " + hex(t.content) + " " + hex(t.content_lo);
        for (double m : t.m) out += " " + hex(m);
    }
    out += "\n";
}

}  // namespace

std::string kernel_data(const KernelFacts& f, const std::vector<std::optional<std::vector<RoundedPiece>>>& tables) {
    const ExactKernel& k = f.kernel;
    std::string out = "mollify-table 4\n";
    out += "generator mollify-gen " + generator_version() + "\n";
    out += "spec " + f.spec + "\n";
    out += "dim " + std::to_string(k.dim) + "\n";
    out += "support " + hex(1.0) + "\n";
    out += "smoothness " + std::to_string(k.claims.smoothness) + "\n";
    out += "order " + std::to_string(k.claims.order) + "\n";
    out += "parity " + std::to_string(k.W.parity) + "\n";
    out += "normalisation " + hex(round_to_double(k.normalisation)) + "\n";
    out += "normalisation_exact " + k.normalisation.to_string() + "\n";
    out += k.claims.no_potential.empty() ? "has_potential 1\n" : "has_potential 0\n";
    for (int i = 0; i < table::quantity_count; ++i) {
        const auto& q = tables[static_cast<std::size_t>(i)];
        out += std::string("quantity ") + table::quantity_names[i] + " " + std::to_string(q ? q->size() : 0) + "\n";
        if (!q) continue;
        for (const RoundedPiece& p : *q) {
            out += "piece " + hex(p.lo) + " " + hex(p.hi) + " " + std::to_string(p.terms.size()) + "\n";
            for (const RoundedTerm& t : p.terms) write_term(out, t);
        }
    }
    out += "end\n";
    return out + TableFile::checksum_line(out);
}

std::string kernel_data_path(const std::string& spec, int dim) {
    std::string path = kernel_header(spec, dim);
    return path.substr(0, path.size() - 4) + ".table";  // .hpp -> .table
}

}  // namespace mollify::gen
