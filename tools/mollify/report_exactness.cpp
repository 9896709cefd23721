// Report section 1: the default catalogue generated anew by mollify-gen (every
// certificate checked in exact arithmetic), compared with the checked-in
// generated/, the errata of the seed documents (mollify-gen errata) and of
// published codes (mollify-gen errata --codes).
#include "process.hpp"
#include "report.hpp"

#include <mollify/error.hpp>

#include <nlohmann/json.hpp>

#include <fstream>
#include <map>
#include <sstream>

namespace fs = std::filesystem;

namespace mollify::app {

namespace {

// Files under `a` and `b` that differ or exist on one side only.
std::vector<std::string> differences(const fs::path& a, const fs::path& b) {
    std::map<std::string, int> seen;  // 1: in a, 2: in b, 3: both
    for (const fs::path& root : {a, b})
        for (const auto& e : fs::recursive_directory_iterator(root))
            if (e.is_regular_file()) seen[fs::relative(e.path(), root).string()] |= root == a ? 1 : 2;
    std::vector<std::string> diff;
    for (const auto& [name, where] : seen) {
        if (where != 3) diff.push_back(name + (where == 1 ? " (only in the new output)" : " (only in generated/)"));
        else if (read_text(a / name) != read_text(b / name)) diff.push_back(name + " (differs)");
    }
    return diff;
}

std::string family(const std::string& spec) {
    const std::size_t colon = spec.find(':');
    return colon == std::string::npos ? "classic" : spec.substr(0, colon);
}

// Certificates per family from catalogue.json; failures named.
std::string certificates(const fs::path& catalogue, SectionResult& r) {
    const nlohmann::json cat = nlohmann::json::parse(read_text(catalogue));
    struct Count {
        long kernels = 0, checks = 0, passed = 0;
    };
    std::map<std::string, Count> by_family;
    for (const auto& k : cat.at("kernels")) {
        Count& c = by_family[family(k.at("spec").get<std::string>())];
        ++c.kernels;
        for (const auto& cert : k.at("certificates")) {
            ++c.checks;
            if (cert.at("passed").get<bool>()) ++c.passed;
            else
                r.failures.push_back("certificate failed: " + k.at("spec").get<std::string>() + " D = " +
                                     std::to_string(k.at("dim").get<int>()) + ": " + cert.at("what").get<std::string>());
        }
    }
    Table t{{"family", "kernels (spec × D)", "certificates", "exact and passed"}, {}};
    Count all;
    for (const auto& [f, c] : by_family) {
        t.add({f, std::to_string(c.kernels), std::to_string(c.checks), std::to_string(c.passed)});
        all.kernels += c.kernels, all.checks += c.checks, all.passed += c.passed;
    }
    t.add({"**all**", std::to_string(all.kernels), std::to_string(all.checks), std::to_string(all.passed)});
    return t.markdown();
}

// mollify-gen errata prints "document | where | entry | printed: .. | exact: .. | note"
// per discrepancy and a last line "checked N entries, M discrepancies".
std::string errata(const std::string& text, Output& out) {
    std::istringstream in(text);
    std::string line, last;
    Table all{{"document", "where", "entry", "printed", "exact", "note"}, {}};
    std::map<std::pair<std::string, std::string>, int> count;
    while (std::getline(in, line)) {
        std::vector<std::string> f;
        std::size_t at = 0;
        for (std::size_t bar; (bar = line.find(" | ", at)) != std::string::npos; at = bar + 3) f.push_back(line.substr(at, bar - at));
        f.push_back(line.substr(at));
        if (f.size() != 6) {
            if (!line.empty()) last = line;
            continue;
        }
        ++count[{f[0], f[1]}];
        all.add(f);
    }
    out.csv("errata.csv", all);
    Table t{{"document", "where", "errata"}, {}};
    for (const auto& [key, n] : count) t.add({key.first, key.second, std::to_string(n)});
    std::string md = "`mollify-gen errata`: " + last + " (every printed value of the seed documents transcribed in "
                     "`generator/transcriptions/`, compared with the exact value). Per table or equation:\n\n" + t.markdown();
    md += "\nEvery entry, with the printed and the exact value: [exactness/errata.csv](exactness/errata.csv). The first "
          "of them:\n\n";
    Table head{all.columns, {}};
    for (std::size_t i = 0; i < all.rows.size() && i < 8; ++i) head.add(all.rows[i]);
    return md + head.markdown();
}

// mollify-gen errata --codes prints "code | source | entry | published: .. |
// exact: .. | published/exact: .. | diagnosis" per transcribed constant and a
// last line "checked N published constants of codes, M wrong".
std::string code_errata(const std::string& text, Output& out) {
    std::istringstream in(text);
    std::string line, last;
    Table all{{"code", "source", "entry", "published", "exact", "published/exact", "diagnosis"}, {}};
    Table wrong{all.columns, {}};
    std::map<std::string, std::pair<int, int>> per_code;  // right, wrong
    auto strip = [](const std::string& field, const std::string& label) {
        return field.rfind(label, 0) == 0 ? field.substr(label.size()) : field;
    };
    while (std::getline(in, line)) {
        std::vector<std::string> f;
        std::size_t at = 0;
        for (std::size_t bar; (bar = line.find(" | ", at)) != std::string::npos; at = bar + 3) f.push_back(line.substr(at, bar - at));
        f.push_back(line.substr(at));
        if (f.size() != 7) {
            if (!line.empty()) last = line;
            continue;
        }
        f[3] = strip(f[3], "published: ");
        f[4] = strip(f[4], "exact: ");
        f[5] = strip(f[5], "published/exact: ");
        const bool right = f[6].rfind("right", 0) == 0 || f[6].rfind("not checked", 0) == 0;
        (right ? per_code[f[0]].first : per_code[f[0]].second) += 1;
        all.add(f);
        if (!right) wrong.add(f);
    }
    out.csv("code_errata.csv", all);
    Table counts{{"code", "constants right", "wrong"}, {}};
    for (const auto& [code, n] : per_code) counts.add({code, std::to_string(n.first), std::to_string(n.second)});
    return "`mollify-gen errata --codes`: " + last +
           " (kernel constants of public SPH and N-body codes transcribed as published, with repository, file and "
           "commit or issue, in `generator/transcriptions/codes/`; each compared with the exact value in the code's "
           "own convention). Per code:\n\n" + counts.markdown() + "\nThe wrong ones, with the diagnosis from the exact ratio:\n\n" +
           wrong.markdown() + "\nEvery entry, right ones included: [exactness/code_errata.csv](exactness/code_errata.csv).\n";
}

}  // namespace

void report_exactness(const ReportContext& ctx, Output& out, SectionResult& r) {
    const std::string gen = (ctx.tools / "mollify-gen").string();
    const fs::path fresh = out.staging() / "generated";
    const ProcessResult emit = run_process(gen, {"emit", "--out", fresh.string()}, {}, "cmake --build build");
    if (!emit.ok()) fail("mollify-gen emit failed (exit status " + std::to_string(emit.exit_status) + "): " + emit.err);
    r.markdown += "`mollify-gen emit` generated the default catalogue anew; each kernel's certificates are "
                  "proved in exact arithmetic (rationals, π and logarithms kept symbolic):\n\n";
    r.markdown += certificates(fresh / "catalogue.json", r) + "\n";
    std::error_code ec;
    if (fs::is_directory(ctx.generated, ec)) {
        const std::vector<std::string> diff = differences(fresh, ctx.generated);
        r.markdown += diff.empty() ? "The new tables are identical, byte for byte, to the checked-in `generated/` (`" +
                                         fs::proximate(ctx.generated, ec).string() + "`).\n\n"
                                   : "**The new tables differ from the checked-in `generated/`:**\n\n";
        for (const std::string& d : diff) {
            r.markdown += "- " + d + "\n";
            r.failures.push_back("generated/" + d);
        }
    } else {
        r.markdown += "No checked-in `generated/` at " + ctx.generated.string() + " to compare with.\n\n";
    }
    fs::copy_file(fresh / "catalogue.json", out.staging() / "catalogue.json");
    fs::remove_all(fresh);  // the tables are in generated/; the catalogue is kept

    const ProcessResult e = run_process(gen, {"errata"});
    if (!e.ok()) fail("mollify-gen errata failed (exit status " + std::to_string(e.exit_status) + "): " + e.err);
    r.markdown += "\n### Errata of the seed documents\n\n" + errata(e.out, out);

    const ProcessResult c = run_process(gen, {"errata", "--codes"});
    if (!c.ok()) fail("mollify-gen errata --codes failed (exit status " + std::to_string(c.exit_status) + "): " + c.err);
    r.markdown += "\n### Errata in published codes\n\n" + code_errata(c.out, out);
}

}  // namespace mollify::app
