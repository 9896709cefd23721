// `mollify-gen errata`: every value the source documents print (transcribed,
// printing errors included, in generator/transcriptions/*.json; see the
// README there) compared with the value the exact core computes. Nothing
// correct is hard-coded: each exact value comes from make_kernel, the
// potential, exponent_method, vandermonde_weights, wendland_shape, ...
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace mollify::gen {

struct Discrepancy {
    std::string document;  // "Anderson 2014 (seed 000)"
    std::string where;     // "Table 3", "Appendix B", "eq. (9)"
    std::string entry;     // the transcription's label, extended by the coefficient or part compared
    std::string printed;   // the printed value (short_string / Exact::to_string form)
    std::string exact;     // the exact value in the same form
    std::string remark;    // why, when it can be said; may be empty
};

struct ErrataReport {
    int checked = 0;  // values compared (per coefficient for formulas)
    std::vector<Discrepancy> discrepancies;
};

// Reads every *.json in `dir` (sorted by file name) and compares each
// printed value with the exact one. A malformed transcription (unknown
// quantity, missing field, bad number) throws Error naming file and entry.
ErrataReport check_errata(const std::filesystem::path& dir);

// "document | where | entry | printed: VALUE | exact: VALUE" and, when the
// remark is non-empty, " | remark".
std::string format_line(const Discrepancy& d);

}  // namespace mollify::gen
