// The samples CSV reader with std::from_chars (README, "Dependencies": three
// numeric columns need no CSV library; from_chars is exact, locale-free and
// reports where a number ends).
#include "samples_csv.hpp"

#include <mollify/error.hpp>
#include <mollify/spec.hpp>

#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <optional>
#include <sstream>

namespace mollify::app {

namespace {

constexpr std::array<std::string_view, 3> column_names = {"r", "h", "value"};

std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
    return s;
}

std::string_view unquote(std::string_view s) {
    if (s.size() >= 2 && s.front() == '"' && s.back() == '"') return s.substr(1, s.size() - 2);
    return s;
}

// The text as it appears in a message: quoted, shortened, control bytes escaped.
std::string shown(std::string_view s) {
    std::string out = "\"";
    for (char c : s.substr(0, 40)) {
        if (static_cast<unsigned char>(c) < 0x20 || c == '"' || c == '\\' || static_cast<unsigned char>(c) >= 0x7f) {
            static constexpr char hex[] = "0123456789abcdef";
            const auto u = static_cast<unsigned char>(c);
            out += std::string("\\x") + hex[u >> 4] + hex[u & 15];
        } else {
            out += c;
        }
    }
    if (s.size() > 40) out += "...";
    return out + "\"";
}

std::vector<std::string_view> split(std::string_view line) {
    std::vector<std::string_view> fields;
    for (;;) {
        const std::size_t comma = line.find(',');
        fields.push_back(trim(line.substr(0, comma)));
        if (comma == std::string_view::npos) return fields;
        line.remove_prefix(comma + 1);
    }
}

struct Where {
    const std::string& origin;
    std::size_t line;
    [[noreturn]] void fail(const std::string& why) const {
        mollify::fail(origin + ":" + std::to_string(line) + ": " + why);
    }
};

// Column index of r, h and value in the header.
std::array<std::size_t, 3> read_header(std::string_view line, const Where& at) {
    const auto fields = split(line);
    std::array<std::size_t, 3> index{};
    std::array<bool, 3> seen{};
    const std::string expected = " (the header names the columns r, h, value, e.g. \"r,h,value\")";
    if (fields.size() != 3)
        at.fail("the header has " + std::to_string(fields.size()) + " columns, 3 expected" + expected);
    for (std::size_t c = 0; c < 3; ++c) {
        const std::string_view name = unquote(fields[c]);
        std::size_t k = 0;
        while (k < 3 && column_names[k] != name) ++k;
        if (k == 3) at.fail("column " + std::to_string(c + 1) + ": " + shown(fields[c]) + " is not a column name" + expected);
        if (seen[k]) at.fail("column " + std::to_string(c + 1) + ": " + shown(fields[c]) + " appears twice" + expected);
        seen[k] = true;
        index[k] = c;
    }
    return index;
}

double read_number(std::string_view field, std::size_t column, std::string_view name, const Where& at) {
    const std::string where = "column " + std::to_string(column + 1) + " (" + std::string(name) + "): ";
    std::string_view text = unquote(field);
    if (text.size() > 1 && text.front() == '+' && text[1] != '-') text.remove_prefix(1);  // from_chars takes no '+'
    double x = 0;
    if (const std::optional<double> hex = hex_float(text)) {  // C's %a, Python's float.hex: the grammar's (spec.hpp)
        if (std::isnan(*hex)) at.fail(where + shown(field) + " is not a number");
        if (std::isinf(*hex)) at.fail(where + shown(field) + " is out of the range of a double");
        x = *hex;
    } else {
        const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), x);
        if (text.empty()) at.fail(where + "empty field, a number expected");
        if (ec == std::errc::result_out_of_range) at.fail(where + shown(field) + " is out of the range of a double");
        if (ec != std::errc() || end != text.data() + text.size()) at.fail(where + shown(field) + " is not a number");
    }
    if (!std::isfinite(x)) at.fail(where + shown(field) + " is not finite");
    if (name == "r" && x < 0) at.fail(where + "r = " + shown(field) + " is negative (r >= 0 needed)");
    if (name == "h" && x <= 0) at.fail(where + "h = " + shown(field) + " is not positive (h > 0 needed)");
    return x;
}

}  // namespace

SampleTable parse_samples_csv(std::string_view text, const std::string& origin) {
    SampleTable table;
    std::array<std::size_t, 3> index{};
    bool have_header = false;
    std::size_t line_number = 0;
    while (!text.empty()) {
        const std::size_t newline = text.find('\n');
        const std::string_view line = text.substr(0, newline);
        text.remove_prefix(newline == std::string_view::npos ? text.size() : newline + 1);
        ++line_number;
        if (trim(line).empty()) continue;
        const Where at{origin, line_number};
        if (!have_header) {
            index = read_header(line, at);
            have_header = true;
            continue;
        }
        const auto fields = split(line);
        if (fields.size() != 3)
            at.fail("this row has " + std::to_string(fields.size()) + (fields.size() == 1 ? " field" : " fields") + ", 3 expected (r, h, value): " +
                    shown(trim(line)));
        table.r.push_back(read_number(fields[index[0]], index[0], "r", at));
        table.h.push_back(read_number(fields[index[1]], index[1], "h", at));
        table.value.push_back(read_number(fields[index[2]], index[2], "value", at));
    }
    if (!have_header) fail(origin + ": empty: a header line r,h,value and one row per sample expected");
    if (table.r.empty()) fail(origin + ": a header and no rows: one row per sample expected");
    return table;
}

SampleTable read_samples_csv(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) fail("cannot read samples file " + file.string() + " (it does not exist or is not readable)");
    std::ostringstream s;
    s << in.rdbuf();
    if (in.bad()) fail("error reading samples file " + file.string());
    return parse_samples_csv(s.str(), file.string());
}

}  // namespace mollify::app
