// `mollify-gen errata --codes`: the kernel constants that public SPH and
// N-body codes publish (transcribed as printed, errors included, with
// repository, file and commit or issue number, in
// generator/transcriptions/codes/*.json; see the README there), each
// compared with the exact value in the code's own convention (support in
// units of its h) and, when they differ, diagnosed exactly from the ratio:
// a constant factor, another dimension's constant, a support convention,
// a gradient off by a power of q, a wrong sign, or another kernel's
// gradient (a mismatched pair). Every exact value comes from the generator
// (make_kernel), never from a table.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace mollify::gen {

struct CodeVerdict {
    std::string code;       // "PySPH (pypr/pysph)"
    std::string source;     // "pysph/base/kernels.py @ 4f733660^", "issue #421"
    std::string entry;      // "QuinticSpline, D = 3, W"
    std::string published;  // as printed (an exact constant, or the printed expression)
    std::string exact;      // the exact value in the code's convention
    std::string ratio;      // published/exact: "1", "360/359", "q^-1", "2 (D = 1)", ...
    std::string diagnosis;  // "right", or why it is wrong
    bool right = false;
};

struct CodeErrataReport {
    std::vector<CodeVerdict> verdicts;  // in file-name order, then entry order
    int wrong() const;
};

// Reads every *.json in `dir` (sorted by file name). A malformed
// transcription (unknown quantity, missing or ill-typed field, a shape
// whose support disagrees with the stated one, a spec that is not a
// kernel) throws Error naming file, entry and field.
CodeErrataReport check_code_errata(const std::filesystem::path& dir);

// "code | source | entry | published: X | exact: Y | published/exact: R | diagnosis".
std::string format_line(const CodeVerdict& v);

}  // namespace mollify::gen
