#include <mollify/table_file.hpp>

#include <mollify/detail/show.hpp>
#include <mollify/error.hpp>

#include <boost/crc.hpp>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <fstream>
#include <sstream>
#include <vector>

namespace mollify {

struct TableFile::Storage {
    int version = 0;
    std::string spec, normalisation_exact;
    // deques: elements stay in place while more are appended, so the
    // pointers in `kernel` stay valid.
    std::deque<std::vector<double>> doubles;
    std::deque<std::vector<table::Term>> terms;
    std::deque<std::vector<table::Piece>> pieces;
    table::Kernel kernel{};
};

namespace {

// The file's lines, one at a time, split into fields; every error names the
// origin and the line.
class Reader {
public:
    Reader(const std::string& text, std::string origin) : in_(text), origin_(std::move(origin)) {}

    [[noreturn]] void bad(const std::string& what) const {
        fail(origin_ + ":" + std::to_string(line_number_) + ": " + what);
    }

    // The next line, which must start with `key`; returns the rest.
    std::string line(const std::string& key) {
        if (!std::getline(in_, current_)) {
            ++line_number_;
            bad("the file ends where '" + key + "' was expected");
        }
        ++line_number_;
        if (current_ != key && current_.compare(0, key.size() + 1, key + " ") != 0)
            bad("'" + current_ + "' is not a '" + key + "' line");
        const std::string rest = current_.size() > key.size() ? current_.substr(key.size() + 1) : std::string();
        fields_.clear();
        std::istringstream f(rest);
        for (std::string s; f >> s;) fields_.push_back(s);
        next_ = 0;
        return rest;
    }

    // The fields of the current line, one after the other.
    std::string field(const char* what) {
        if (next_ >= fields_.size()) bad("'" + current_ + "' misses " + what);
        return fields_[next_++];
    }
    int integer(const char* what) {
        const std::string s = field(what);
        char* end = nullptr;
        errno = 0;
        const long v = std::strtol(s.c_str(), &end, 10);
        if (s.empty() || *end != '\0' || errno != 0 || v < -1000000 || v > 1000000)
            bad(std::string(what) + " '" + s + "' is not an integer");
        return static_cast<int>(v);
    }
    // Hex-floats as written (strtod reads them exactly), "inf" for infinity.
    double number(const char* what) {
        const std::string s = field(what);
        char* end = nullptr;
        const double v = std::strtod(s.c_str(), &end);
        if (s.empty() || *end != '\0' || s.find_first_of("xXi") == std::string::npos)
            bad(std::string(what) + " '" + s + "' is not a hex-float double");
        if (std::isnan(v)) bad(std::string(what) + " '" + s + "' is NaN (no number of a table is)");
        return v;
    }
    // The next field without taking it ("" at the end of the line).
    std::string peek() const { return next_ < fields_.size() ? fields_[next_] : std::string(); }
    void done() {
        if (next_ != fields_.size()) bad("'" + current_ + "' has more fields than expected");
    }
    bool at_end() {
        std::string rest;
        return !(in_ >> rest);
    }
    // Where the next line starts, as a byte offset into the text.
    std::size_t offset() { return static_cast<std::size_t>(in_.tellg()); }

private:
    std::istringstream in_;
    std::string origin_, current_;
    std::vector<std::string> fields_;
    std::size_t next_ = 0;
    int line_number_ = 0;
};

table::Basis basis(Reader& r) {
    const std::string name = r.field("basis");
    for (table::Basis b : {table::Basis::one, table::Basis::sqrt_power, table::Basis::arcsech, table::Basis::log,
                           table::Basis::arcsin})
        if (name == table::basis_name(b)) return b;
    r.bad("basis '" + name + "' is not one of one, sqrt_power, arcsech, log, arcsin");
}

table::Var var(Reader& r) {
    const std::string name = r.field("var");
    for (table::Var v : {table::Var::r, table::Var::r2, table::Var::shifted})
        if (name == table::var_name(v)) return v;
    r.bad("var '" + name + "' is not one of r, r2, shifted");
}

const double* stored(TableFile::Storage& s, std::vector<double> v) {
    s.doubles.push_back(std::move(v));
    return s.doubles.back().data();
}

// table::Term::split: the exactness it claims is checked here (a wrong
// claim would be a silently wrong value): m non-negative integers below
// 2^53, c_k within an ulp of content m_k, and Horner's bounds at the grid
// 2^-split below 2^53 over q <= edge + 2^-split, the term's domain
// (table::split_is_exact, as the generator proved it).
void split(Reader& r, TableFile::Storage& s, table::Term& t) {
    r.field("split");
    t.split = r.integer("split");
    if (t.split < 1 || t.split > 26) r.bad("split = " + std::to_string(t.split) + " is outside 1..26");
    if (t.var != table::Var::r || t.n < 2) r.bad("split on a term that is not a polynomial in r of 2 or more coefficients");
    t.content = r.number("content");
    t.content_lo = r.number("content_lo");
    if (!table::content_in_range(t.content))
        r.bad("content = " + detail::show(t.content) + " is outside [2^-60, 2^60] (it joins the scale h^p)");
    std::vector<double> m;
    for (int k = 0; k < t.n; ++k) {
        const double x = r.number("an integer coefficient m_k");
        if (!(x >= 0 && x < 0x1p53 && x == std::floor(x))) r.bad("m_k = " + std::to_string(x) + " is not an integer in [0, 2^53)");
        if (!(std::abs(t.content * x - t.c[k]) <= std::abs(t.c[k]) * 0x1p-51))
            r.bad("content * m_k = " + std::to_string(t.content * x) + " is not c_k = " + std::to_string(t.c[k]));
        m.push_back(x);
    }
    if (!table::split_is_exact(m.data(), t.n, std::abs(t.edge), t.split))
        r.bad("split = " + std::to_string(t.split) + " leaves Horner's rule inexact (a partial sum needs more than 53 bits)");
    t.m = stored(s, std::move(m));
}

table::Term term(Reader& r, TableFile::Storage& s) {
    r.line("term");
    table::Term t{};
    t.basis = basis(r);
    t.s_power = r.integer("s_power");
    t.var = var(r);
    t.edge = r.number("edge");
    t.edge_lo = r.number("edge_lo");
    t.edge_power = r.integer("edge_power");
    t.low = r.integer("low");
    t.centre = r.number("centre");
    t.centre_lo = r.number("centre_lo");
    t.n = r.integer("n");
    if (t.n < 1 || t.n > 10000) r.bad("n = " + std::to_string(t.n) + " is outside 1..10000");
    std::vector<double> c;
    for (int k = 0; k < t.n; ++k) c.push_back(r.number("a coefficient c_k"));
    t.c = stored(s, std::move(c));
    if (r.peek() == "-") {
        r.field("the low parts");
    } else {
        std::vector<double> lo;
        for (int k = 0; k < t.n; ++k) lo.push_back(r.number("a low part c_lo_k (or '-')"));
        t.c_lo = stored(s, std::move(lo));
    }
    if (r.peek() == "plain") {
        r.field("plain");
        t.plain = r.integer("plain");
        if (t.plain < 0 || t.plain > t.n - 2) r.bad("plain = " + std::to_string(t.plain) + " is outside 0..n - 2");
    }
    if (r.peek() == "split") split(r, s, t);
    r.done();
    return t;
}

table::Quantity quantity(Reader& r, TableFile::Storage& s, int index) {
    r.line("quantity");
    const std::string name = r.field("the quantity's name");
    if (name != table::quantity_names[index])
        r.bad("quantity '" + name + "' where '" + table::quantity_names[index] + "' was expected (table::QuantityId order)");
    const int npieces = r.integer("npieces");
    if (npieces < 0 || npieces > 100000) r.bad("npieces = " + std::to_string(npieces) + " is outside 0..100000");
    r.done();
    if (npieces == 0) return {nullptr, 0};
    std::vector<table::Piece> pieces;
    for (int p = 0; p < npieces; ++p) {
        r.line("piece");
        table::Piece piece{};
        piece.lo = r.number("lo");
        piece.hi = r.number("hi");
        piece.nterms = r.integer("nterms");
        if (piece.nterms < 0 || piece.nterms > 100000) r.bad("nterms = " + std::to_string(piece.nterms) + " is outside 0..100000");
        r.done();
        std::vector<table::Term> terms;
        for (int t = 0; t < piece.nterms; ++t) terms.push_back(term(r, s));
        if (!terms.empty()) {
            s.terms.push_back(std::move(terms));
            piece.terms = s.terms.back().data();
        }
        // The pieces tile [0, inf) in order (the evaluators select a piece
        // by the next one's lo: a gap or an overlap would be a silently
        // wrong value).
        const double from = p == 0 ? 0.0 : pieces.back().hi;
        if (piece.lo != from || !(piece.hi > piece.lo))
            r.bad("piece [" + detail::show(piece.lo) + ", " + detail::show(piece.hi) + ") does not follow " +
                  (p == 0 ? std::string("0") : "the piece before it, which ends at " + detail::show(from)));
        if (p + 1 == npieces && piece.hi != table::infinity)
            r.bad("the last piece ends at " + detail::show(piece.hi) + ", not inf");
        pieces.push_back(piece);
    }
    s.pieces.push_back(std::move(pieces));
    return {s.pieces.back().data(), npieces};
}

// Version 4's last line, "checksum crc32 <8 hex digits>": the CRC-32 (as
// zlib's crc32 and Python's zlib.crc32 compute it) of every byte before that
// line. Checked after the fields, so a malformed file is named by its field.
void check_sum(Reader& r, const std::string& text) {
    const std::size_t covered = r.offset();
    r.line("checksum");
    if (r.field("the checksum's kind") != "crc32") r.bad("checksum kind is not crc32");
    const std::string written = r.field("the CRC-32");
    r.done();
    const std::string line = TableFile::checksum_line(std::string_view(text).substr(0, covered));
    const std::string actual = line.substr(std::string("checksum crc32 ").size(), 8);
    if (written != actual)
        r.bad("checksum crc32 " + written + " is not the file's (" + actual +
              "): the file was changed after mollify-gen wrote it (regenerate it)");
}

int single_integer(Reader& r, const char* key) {
    r.line(key);
    const int v = r.integer(key);
    r.done();
    return v;
}

double single_number(Reader& r, const char* key) {
    r.line(key);
    const double v = r.number(key);
    r.done();
    return v;
}

}  // namespace

TableFile::TableFile(std::unique_ptr<Storage> s) : s_(std::move(s)) {}
TableFile::TableFile(TableFile&&) noexcept = default;
TableFile& TableFile::operator=(TableFile&&) noexcept = default;
TableFile::~TableFile() = default;

const table::Kernel& TableFile::kernel() const { return s_->kernel; }
int TableFile::version() const { return s_->version; }

std::string TableFile::checksum_line(std::string_view body) {
    boost::crc_32_type crc;
    crc.process_bytes(body.data(), body.size());
    char hex[16];
    std::snprintf(hex, sizeof hex, "%08x", static_cast<unsigned>(crc.checksum()));
    return std::string("checksum crc32 ") + hex + "\n";
}

TableFile TableFile::parse(const std::string& text, const std::string& origin) {
    auto s = std::make_unique<Storage>();
    Reader r(text, origin);
    r.line("mollify-table");
    const std::string version = r.field("the format version");
    if (version != "1" && version != "2" && version != "3" && version != "4")
        r.bad("format version '" + version + "' is not 1, 2, 3 or 4 (a newer mollify-gen wrote it?)");
    r.done();
    s->version = version[0] - '0';
    r.line("generator");
    s->spec = r.line("spec");
    if (s->spec.empty() || s->spec.find(' ') != std::string::npos) r.bad("spec '" + s->spec + "' is not a kernel spec");
    table::Kernel& k = s->kernel;
    k.spec = s->spec.c_str();
    k.dim = single_integer(r, "dim");
    if (k.dim < 1 || k.dim > 3) r.bad("dimension " + std::to_string(k.dim) + " is outside 1..3");
    k.support = single_number(r, "support");
    k.smoothness = single_integer(r, "smoothness");
    k.order = single_integer(r, "order");
    k.parity = single_integer(r, "parity");
    k.normalisation = single_number(r, "normalisation");
    s->normalisation_exact = r.line("normalisation_exact");
    k.normalisation_exact = s->normalisation_exact.c_str();
    const int has_potential = single_integer(r, "has_potential");
    if (has_potential != 0 && has_potential != 1) r.bad("has_potential " + std::to_string(has_potential) + " is not 0 or 1");
    k.has_potential = has_potential == 1;
    for (int i = 0; i < table::quantity_count; ++i) k.quantities[i] = quantity(r, *s, i);
    r.line("end");
    r.done();
    if (s->version >= 4) check_sum(r, text);
    if (!r.at_end()) r.bad(s->version >= 4 ? "text after the checksum" : "text after 'end'");
    return TableFile(std::move(s));
}

TableFile TableFile::load(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail("cannot read the table file " + path.string());
    std::ostringstream text;
    text << in.rdbuf();
    return parse(text.str(), path.string());
}

}  // namespace mollify
