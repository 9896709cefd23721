// Samples of someone's kernel as CSV, from any language (`mollify verify
// --samples FILE.csv`): a header line naming the columns r, h and value (in
// any order, names optionally in double quotes, as R's write.csv writes
// them), then one row per sample, comma-separated numbers as C's strtod,
// Python's repr and Fortran's ES format write them. Blank lines are skipped,
// CRLF line ends accepted.
//
// Every error is a mollify::Error naming the file, the line, the column and
// the bad text: a row with too few or too many fields, a field that is not a
// number, r < 0, h <= 0, a non-finite number.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace mollify::app {

struct SampleTable {
    std::vector<double> r, h, value;  // one entry per row, in file order
};

// Parses CSV text; `origin` names it in errors ("FILE:LINE: ...").
SampleTable parse_samples_csv(std::string_view text, const std::string& origin);

// Reads and parses a file; a missing or unreadable file is an Error naming it.
SampleTable read_samples_csv(const std::filesystem::path& file);

}  // namespace mollify::app
