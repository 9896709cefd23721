// check_toml_characters (toml_guard.hpp): a lexer of TOML's outline (comments,
// the four string forms, keys against values, brackets), just enough to know
// where a non-ASCII byte stands.
#include "toml_guard.hpp"

#include <mollify/error.hpp>

#include <vector>

namespace mollify::app {

namespace {

enum class Mode { normal, comment, basic, literal, ml_basic, ml_literal };

bool non_ascii(char c) { return static_cast<unsigned char>(c) >= 0x80; }

class Lexer {
public:
    Lexer(std::string_view text, const std::string& origin) : text_(text), origin_(origin) {}

    void run() {
        for (i_ = 0; i_ < text_.size(); ++i_) {
            switch (mode_) {
                case Mode::normal: normal(); break;
                case Mode::comment:
                    if (text_[i_] == '\n') normal();
                    break;
                case Mode::basic: basic(); break;
                case Mode::literal: in_string('\''); break;
                case Mode::ml_basic: ml_basic(); break;
                case Mode::ml_literal:
                    if (text_.substr(i_, 3) == "'''") close_multi_line('\'');
                    else if (text_[i_] == '\n') ++line_;
                    break;
            }
        }
    }

private:
    [[noreturn]] void reject(const std::string& why) const {
        fail(origin_ + ":" + std::to_string(line_) + ": " + why);
    }

    void newline() {
        ++line_;
        mode_ = Mode::normal;
        if (brackets_.empty()) {
            expect_key_ = true;
            in_header_ = false;
        }
    }

    void open_string(char quote) {
        key_string_ = expect_key_;
        if (text_.substr(i_, 3) == std::string(3, quote)) {
            mode_ = quote == '"' ? Mode::ml_basic : Mode::ml_literal;
            i_ += 2;
        } else {
            mode_ = quote == '"' ? Mode::basic : Mode::literal;
        }
    }

    // Up to two more quotes belong to the string ("""a"""" ends a"): consume the run.
    void close_multi_line(char quote) {
        std::size_t end = i_ + 3;
        while (end < text_.size() && end < i_ + 5 && text_[end] == quote) ++end;
        i_ = end - 1;
        mode_ = Mode::normal;
    }

    void normal() {
        const char c = text_[i_];
        switch (c) {
            case '\n': newline(); return;
            case '#': mode_ = Mode::comment; return;
            case '"':
            case '\'': open_string(c); return;
            case '=':
                if (!in_header_) expect_key_ = false;
                return;
            case '[':
                if (expect_key_ && brackets_.empty()) {
                    in_header_ = true;
                } else {
                    brackets_.push_back('[');
                    expect_key_ = false;
                }
                return;
            case '{':
                brackets_.push_back('{');
                expect_key_ = true;
                return;
            case ']':
            case '}':
                if (!in_header_ && !brackets_.empty()) brackets_.pop_back();
                expect_key_ = false;
                return;
            case ',': expect_key_ = !brackets_.empty() && brackets_.back() == '{'; return;
            default:
                if (non_ascii(c))
                    reject("a non-ASCII character outside a string or comment (TOML keys and values are ASCII; "
                           "write text in quotes)");
        }
    }

    void in_string(char quote) {
        const char c = text_[i_];
        if (c == quote) mode_ = Mode::normal;
        else if (c == '\n') newline();  // an unterminated string: toml++ says so
        else if (non_ascii(c) && key_string_) reject("a non-ASCII character in a key (keys must be ASCII)");
    }

    void basic() {
        if (text_[i_] == '\\' && i_ + 1 < text_.size() && text_[i_ + 1] != '\n') {
            ++i_;  // the escaped character
            if (non_ascii(text_[i_]) && key_string_) reject("a non-ASCII character in a key (keys must be ASCII)");
            return;
        }
        in_string('"');
    }

    void ml_basic() {
        const char c = text_[i_];
        if (text_.substr(i_, 3) == "\"\"\"") return close_multi_line('"');
        if (c == '\n') ++line_;
        if (c != '\\' || i_ + 1 >= text_.size()) return;
        // A backslash: an escape, or a line-ending backslash that swallows the
        // whitespace after it; toml++ classifies the next non-blank character.
        std::size_t j = i_ + 1;
        const bool line_ending = text_[j] == ' ' || text_[j] == '\t' || text_[j] == '\r' || text_[j] == '\n';
        if (line_ending) {
            while (j < text_.size() && (text_[j] == ' ' || text_[j] == '\t' || text_[j] == '\r' || text_[j] == '\n'))
                line_ += text_[j++] == '\n';
            --j;  // the loop's ++i_ lands on the first non-blank character
        } else if (non_ascii(text_[j])) {
            reject("a non-ASCII character right after a backslash in a multi-line string");
        }
        if (line_ending && j + 1 < text_.size() && non_ascii(text_[j + 1]))
            reject("a non-ASCII character right after a line-ending backslash in a multi-line string (start the "
                   "continued line with an ASCII character)");
        i_ = j;
    }

    std::string_view text_;
    const std::string& origin_;
    std::size_t i_ = 0, line_ = 1;
    Mode mode_ = Mode::normal;
    bool expect_key_ = true, in_header_ = false, key_string_ = false;
    std::vector<char> brackets_;  // '[' and '{' of values
};

}  // namespace

void check_toml_characters(std::string_view text, const std::string& origin) { Lexer(text, origin).run(); }

std::string ascii_placeholders(std::string_view text) {
    std::string out(text);
    for (char& c : out)
        if (non_ascii(c)) c = 'x';
    return out;
}

}  // namespace mollify::app
