// Tables as data (include/mollify/table_file.hpp): the writer and the reader
// of the text format, and the storage a table read at run time points into.
#include <mollify/error.hpp>
#include <mollify/smoothing.hpp>
#include <mollify/table_file.hpp>

#include <charconv>
#include <cstdio>
#include <deque>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <system_error>
#include <unistd.h>
#include <vector>

namespace mollify {

namespace {

constexpr std::string_view magic = "mollify-table 1";

// %a: the shortest exact hexadecimal form ("0x1.8p+0"); strtod reads it back
// exactly.
std::string hex(double x) {
    if (x == table::infinity) return "inf";
    char buf[64];
    std::snprintf(buf, sizeof buf, "%a", x);
    return buf;
}

template <class Names, class E>
const char* enum_name(const Names& names, E e) {
    return names[static_cast<int>(e)];
}

void write_term(std::string& out, const table::Term& t, int q, int p, int ti, const CoefficientNote& note) {
    out += "term " + std::string(enum_name(table::basis_names, t.basis)) + " " + std::to_string(t.s_power) + " " +
           enum_name(table::var_names, t.var) + " " + hex(t.edge) + " " + hex(t.edge_lo) + " " +
           std::to_string(t.edge_power) + " " + std::to_string(t.low) + " " + hex(t.centre) + " " + hex(t.centre_lo) +
           " " + std::to_string(t.n) + "\n";
    for (int k = 0; k < t.n; ++k) {
        out += "c " + hex(t.c[k]) + " " + hex(t.c_lo ? t.c_lo[k] : 0.0);
        const std::string text = note ? note(q, p, ti, k) : std::string();
        if (!text.empty()) out += "  # " + text;
        out += "\n";
    }
}

// The storage of a table read from text: the table::Kernel points into it.
struct OwnedTable {
    table::Kernel kernel{};
    std::string spec, normalisation_exact;
    std::deque<std::vector<double>> numbers;  // coefficient arrays (a deque: no reallocation moves them)
    std::deque<std::vector<table::Term>> terms;
    std::deque<std::vector<table::Piece>> pieces;
};

// Reads one line at a time, splitting it into whitespace-separated fields
// (a comment dropped); errors name the origin and the line.
class Lines {
public:
    Lines(std::string_view text, std::string_view origin) : text_(text), origin_(origin) {}

    // The next non-empty line's fields; empty at the end of the text.
    std::vector<std::string_view> next() {
        while (pos_ < text_.size()) {
            const std::size_t end = std::min(text_.find('\n', pos_), text_.size());
            std::string_view line = text_.substr(pos_, end - pos_);
            pos_ = end + 1;
            ++number_;
            line_ = line;
            if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
            std::vector<std::string_view> fields;
            std::size_t i = 0;
            while (i < line.size()) {
                while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
                const std::size_t start = i;
                while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
                if (i > start) fields.push_back(line.substr(start, i - start));
            }
            if (!fields.empty()) return fields;
        }
        return {};
    }

    // The whole current line after its first `skip` fields (a free text).
    std::string_view rest_of_line(std::string_view after) const {
        const std::size_t at = line_.find(after);
        std::string_view rest = line_.substr(at + after.size());
        while (!rest.empty() && (rest.front() == ' ' || rest.front() == '\t')) rest.remove_prefix(1);
        while (!rest.empty() && (rest.back() == ' ' || rest.back() == '\r')) rest.remove_suffix(1);
        return rest;
    }

    [[noreturn]] void bad(const std::string& what) const {
        fail(std::string(origin_) + ":" + std::to_string(number_) + ": " + what);
    }

    std::vector<std::string_view> expect(std::string_view keyword, std::size_t fields) {
        std::vector<std::string_view> f = next();
        if (f.empty()) bad("unexpected end of table, expected '" + std::string(keyword) + "'");
        if (f[0] != keyword) bad("expected '" + std::string(keyword) + "', found '" + std::string(f[0]) + "'");
        if (f.size() < fields)
            bad("'" + std::string(keyword) + "' needs " + std::to_string(fields - 1) + " fields, has " +
                std::to_string(f.size() - 1));
        return f;
    }

    double real(std::string_view field, std::string_view what) const {
        if (field == "inf") return table::infinity;
        const std::string s(field);
        char* end = nullptr;
        const double x = std::strtod(s.c_str(), &end);
        if (s.empty() || end != s.c_str() + s.size()) bad(std::string(what) + " '" + s + "' is not a number");
        return x;
    }

    int integer(std::string_view field, std::string_view what, int lo, int hi) const {
        int v = 0;
        const auto [p, ec] = std::from_chars(field.data(), field.data() + field.size(), v);
        if (ec != std::errc() || p != field.data() + field.size() || v < lo || v > hi)
            bad(std::string(what) + " '" + std::string(field) + "' is not an integer in " + std::to_string(lo) + ".." +
                std::to_string(hi));
        return v;
    }

    template <class E, std::size_t N>
    E name_of(std::string_view field, const char* const (&names)[N], std::string_view what) const {
        for (std::size_t i = 0; i < N; ++i)
            if (field == names[i]) return static_cast<E>(i);
        bad("unknown " + std::string(what) + " '" + std::string(field) + "'");
    }

    // The value of `key` at fields[i] (fields[i - 1] must be the key).
    std::string_view keyed(const std::vector<std::string_view>& f, std::size_t i, std::string_view key) const {
        if (i >= f.size() || f[i - 1] != key) bad("expected '" + std::string(key) + "' at field " + std::to_string(i));
        return f[i];
    }

private:
    std::string_view text_, origin_, line_;
    std::size_t pos_ = 0;
    int number_ = 0;
};

// Sanity of what the evaluator relies on: pieces ordered, the last reaching
// to infinity, terms well formed.
void check_piece(const Lines& in, const table::Piece& piece, double previous_hi) {
    if (!(piece.lo == previous_hi) || !(piece.lo < piece.hi)) in.bad("piece bounds out of order");
}

table::Term read_term(Lines& in, OwnedTable& owned) {
    const auto f = in.expect("term", 11);
    table::Term t{};
    t.basis = in.name_of<table::Basis>(f[1], table::basis_names, "basis");
    t.s_power = in.integer(f[2], "s_power", -1000, 1000);
    t.var = in.name_of<table::Var>(f[3], table::var_names, "variable");
    t.edge = in.real(f[4], "edge");
    t.edge_lo = in.real(f[5], "edge_lo");
    t.edge_power = in.integer(f[6], "edge_power", -1000, 1000);
    t.low = in.integer(f[7], "low", -1000, 1000);
    t.centre = in.real(f[8], "centre");
    t.centre_lo = in.real(f[9], "centre_lo");
    t.n = in.integer(f[10], "coefficient count", 1, 100000);
    std::vector<double> c, lo;
    bool exact = true;
    for (int k = 0; k < t.n; ++k) {
        const auto cf = in.expect("c", 3);
        c.push_back(in.real(cf[1], "coefficient"));
        lo.push_back(in.real(cf[2], "low part"));
        exact = exact && lo.back() == 0;
    }
    t.c = owned.numbers.emplace_back(std::move(c)).data();
    t.c_lo = exact ? nullptr : owned.numbers.emplace_back(std::move(lo)).data();
    return t;
}

table::Quantity read_quantity(Lines& in, OwnedTable& owned, int q) {
    const auto f = in.expect("quantity", 4);
    if (f[1] != quantity_names[q])
        in.bad("expected quantity '" + std::string(quantity_names[q]) + "', found '" + std::string(f[1]) + "'");
    const int npieces = in.integer(in.keyed(f, 3, "pieces"), "piece count", 0, 100000);
    std::vector<table::Piece> pieces;
    double hi = 0;
    for (int p = 0; p < npieces; ++p) {
        const auto pf = in.expect("piece", 5);
        table::Piece piece{in.real(pf[1], "piece lo"), in.real(pf[2], "piece hi"), nullptr,
                           in.integer(in.keyed(pf, 4, "terms"), "term count", 0, 100000)};
        check_piece(in, piece, hi);
        hi = piece.hi;
        std::vector<table::Term> terms;
        for (int t = 0; t < piece.nterms; ++t) terms.push_back(read_term(in, owned));
        if (!terms.empty()) piece.terms = owned.terms.emplace_back(std::move(terms)).data();
        pieces.push_back(piece);
    }
    if (npieces > 0 && hi != table::infinity) in.bad("the last piece of " + std::string(quantity_names[q]) + " must reach inf");
    const table::Piece* data = pieces.empty() ? nullptr : owned.pieces.emplace_back(std::move(pieces)).data();
    return {data, npieces};
}

}  // namespace

std::string write_table(const table::Kernel& k, std::string_view banner, const CoefficientNote& note) {
    std::string out;
    out += magic;
    out += "\n";
    std::size_t start = 0;
    while (start < banner.size()) {
        const std::size_t end = std::min(banner.find('\n', start), banner.size());
        out += "# " + std::string(banner.substr(start, end - start)) + "\n";
        start = end + 1;
    }
    out += "kernel " + std::string(k.spec) + " dim " + std::to_string(k.dim) + " support " + hex(k.support) +
           " smoothness " + std::to_string(k.smoothness) + " order " + std::to_string(k.order) + " parity " +
           std::to_string(k.parity) + " has_potential " + (k.has_potential ? "1" : "0") + "\n";
    out += "normalisation " + hex(k.normalisation) + " " + k.normalisation_exact + "\n";
    for (int q = 0; q < table::quantity_count; ++q) {
        const table::Quantity& quantity = k.quantities[q];
        out += "quantity " + std::string(quantity_names[q]) + " pieces " + std::to_string(quantity.npieces) + "\n";
        for (int p = 0; p < quantity.npieces; ++p) {
            const table::Piece& piece = quantity.pieces[p];
            out += "piece " + hex(piece.lo) + " " + hex(piece.hi) + " terms " + std::to_string(piece.nterms) + "\n";
            for (int t = 0; t < piece.nterms; ++t) write_term(out, piece.terms[t], q, p, t, note);
        }
    }
    out += "end\n";
    return out;
}

std::shared_ptr<const table::Kernel> read_table(std::string_view text, std::string_view origin) {
    Lines in(text, origin);
    const auto head = in.next();
    if (head.size() != 2 || head[0] != "mollify-table" || head[1] != "1")
        in.bad("not a mollify table (expected the first line '" + std::string(magic) + "')");
    auto owned = std::make_shared<OwnedTable>();
    table::Kernel& k = owned->kernel;
    const auto f = in.expect("kernel", 14);
    owned->spec = std::string(f[1]);
    k.spec = owned->spec.c_str();
    k.dim = in.integer(in.keyed(f, 3, "dim"), "dimension", 1, 3);
    k.support = in.real(in.keyed(f, 5, "support"), "support");
    if (k.support != 1.0) in.bad("support " + std::string(f[5]) + " is not 1 (tables are emitted with support 1)");
    k.smoothness = in.integer(in.keyed(f, 7, "smoothness"), "smoothness", -1, 1000);
    k.order = in.integer(in.keyed(f, 9, "order"), "order", 0, 1000);
    k.parity = in.integer(in.keyed(f, 11, "parity"), "parity", -1, 1);
    k.has_potential = in.integer(in.keyed(f, 13, "has_potential"), "has_potential", 0, 1) == 1;
    const auto n = in.expect("normalisation", 2);
    k.normalisation = in.real(n[1], "normalisation");
    owned->normalisation_exact = std::string(in.rest_of_line(n[1]));
    k.normalisation_exact = owned->normalisation_exact.c_str();
    for (int q = 0; q < table::quantity_count; ++q) k.quantities[q] = read_quantity(in, *owned, q);
    in.expect("end", 1);
    if (!in.next().empty()) in.bad("text after 'end'");
    if (k.quantities[0].npieces == 0) in.bad("the table has no value");
    return {owned, &owned->kernel};
}

std::shared_ptr<const table::Kernel> read_table_file(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail("cannot read table file '" + path.string() + "'");
    const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    return read_table(text, path.string());
}

void write_file_atomically(const std::filesystem::path& path, std::string_view text) {
    const std::filesystem::path dir = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
    std::filesystem::create_directories(dir);
    std::string temp = (dir / ("." + path.filename().string() + ".tmp-XXXXXX")).string();
    const int fd = ::mkstemp(temp.data());
    if (fd < 0) fail("cannot create a temporary file beside '" + path.string() + "'");
    ::close(fd);
    {
        std::ofstream out(temp, std::ios::binary | std::ios::trunc);
        out.write(text.data(), static_cast<std::streamsize>(text.size()));
        if (!out.flush()) {
            std::filesystem::remove(temp);
            fail("cannot write '" + temp + "'");
        }
    }
    std::error_code ec;
    std::filesystem::rename(temp, path, ec);
    if (ec) {
        std::filesystem::remove(temp);
        fail("cannot rename '" + temp + "' to '" + path.string() + "': " + ec.message());
    }
}

}  // namespace mollify
