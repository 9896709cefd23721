// The driver of `mollify-gen errata`: reads the transcriptions in file-name
// order and hands every entry to the check for its "quantity". The checks
// themselves live with their documents (errata_anderson.cpp,
// errata_franz.cpp, errata_belley.cpp); what they share, in errata_checker.
#include "errata.hpp"

#include "errata_checker.hpp"
#include "error.hpp"

#include <algorithm>
#include <cctype>
#include <fstream>

namespace mollify::gen {

namespace errata {

void Checker::check(const Entry& e) {
    using Check = void (Checker::*)(const Entry&);
    static const std::map<std::string, Check> checks = {
        {"anderson.sigma", &Checker::anderson_sigma},
        {"anderson.c0", &Checker::anderson_c0},
        {"anderson.gamma", &Checker::anderson_gamma},
        {"anderson.alpha", &Checker::anderson_alpha},
        {"anderson.sigma_formula", &Checker::anderson_sigma_formula},
        {"anderson.second_moment", &Checker::anderson_second_moment},
        {"anderson.radii_combination", &Checker::anderson_radii_combination},
        {"anderson.kernel", &Checker::anderson_formula},
        {"anderson.potential", &Checker::anderson_formula},
        {"anderson.potential_gradient", &Checker::anderson_formula},
        {"anderson.potential_hessian", &Checker::anderson_formula},
        {"vandermonde.equidistant", &Checker::vandermonde_equidistant},
        {"wendland.shape", &Checker::wendland_shape_entry},
        {"wendland.combo", &Checker::wendland_combo},
        {"wendland.combo_weights", &Checker::wendland_combo_weights},
        {"wendland_missing.shape", &Checker::wendland_missing},
        {"classic.kernel", &Checker::classic_kernel},
        {"belley.moment", &Checker::belley_moment},
        {"belley.kernel_value", &Checker::belley_kernel_value},
    };
    const auto it = checks.find(e.quantity);
    if (it == checks.end()) e.bad("unknown quantity '" + e.quantity + "'");
    (this->*it->second)(e);
}

}  // namespace errata

namespace {

namespace fs = std::filesystem;
using errata::Checker;
using errata::Entry;
using errata::json;

// The four digits of a year 19xx or 20xx standing alone in `citation`; "" if none.
std::string year_in(const std::string& citation) {
    auto digit = [](char ch) { return std::isdigit(static_cast<unsigned char>(ch)) != 0; };
    for (std::size_t i = 0; i + 4 <= citation.size(); ++i) {
        const bool digits = std::all_of(citation.begin() + static_cast<long>(i),
                                        citation.begin() + static_cast<long>(i + 4), digit);
        const bool alone = (i == 0 || !digit(citation[i - 1])) && (i + 4 == citation.size() || !digit(citation[i + 4]));
        if (digits && alone && (citation.compare(i, 2, "19") == 0 || citation.compare(i, 2, "20") == 0))
            return citation.substr(i, 4);
    }
    return "";
}

// "Christopher R. Anderson, ..." + "... 2014 ..." + "000_..." -> "Anderson 2014 (seed 000)".
std::string document_label(const std::string& citation, const std::string& seed) {
    std::string author = citation.substr(0, citation.find(','));
    if (auto sp = author.find_last_of(' '); sp != std::string::npos) author = author.substr(sp + 1);
    const std::string seed_number = seed.substr(0, seed.find('_'));
    return errata::join({author, year_in(citation)}, " ") + " (seed " + seed_number + ")";
}

// Entry number `index` (from 1) of a file; until its own label and place are
// read, errors name it "#index" at "?".
Entry entry_of(const json& obj, std::size_t index, const std::string& file, const std::string& document,
               ErrataReport& report) {
    Entry e;
    e.file = file;
    e.document = document;
    e.object = &obj;
    e.report = &report;
    e.label = "#" + std::to_string(index);
    e.where = "?";
    if (!obj.is_object()) e.bad("an entry must be an object");
    for (const char* key : {"entry", "where", "quantity"}) {
        auto it = obj.find(key);
        if (it == obj.end() || !it->is_string()) e.bad(std::string("missing string field '") + key + "'");
    }
    e.label = obj["entry"].get<std::string>();
    e.where = obj["where"].get<std::string>();
    e.quantity = obj["quantity"].get<std::string>();
    return e;
}

// Checks one entry; an error from deeper down is prefixed with the entry's
// context unless it names it already.
void check_entry(Checker& checker, const Entry& e) {
    try {
        checker.check(e);
    } catch (const Error& ex) {
        const std::string message = ex.what();
        if (message.rfind(e.context(), 0) == 0) throw;
        e.bad(message);
    }
}

void run_file(Checker& checker, const fs::path& path, ErrataReport& report) {
    const json doc = errata::read_transcription(path, {"document", "seed"});
    const std::string file = path.filename().string();
    const std::string document = document_label(doc["document"].get<std::string>(), doc["seed"].get<std::string>());
    std::size_t index = 0;
    for (const json& obj : doc["entries"]) check_entry(checker, entry_of(obj, ++index, file, document, report));
}

}  // namespace

ErrataReport check_errata(const std::filesystem::path& dir) {
    if (!fs::is_directory(dir)) fail("transcriptions directory " + dir.string() + " does not exist");
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(dir))
        if (entry.is_regular_file() && entry.path().extension() == ".json") files.push_back(entry.path());
    std::sort(files.begin(), files.end(), [](const fs::path& a, const fs::path& b) { return a.filename() < b.filename(); });
    ErrataReport report;
    Checker checker;
    for (const auto& f : files) run_file(checker, f, report);
    return report;
}

std::string format_line(const Discrepancy& d) {
    std::string s = d.document + " | " + d.where + " | " + d.entry + " | printed: " + d.printed + " | exact: " + d.exact;
    if (!d.remark.empty()) s += " | " + d.remark;
    return s;
}

}  // namespace mollify::gen
