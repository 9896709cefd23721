// Tables as data: a kernel's table (table.hpp) written as text and read back
// at run time, so a program can evaluate a kernel that was not compiled in
// (`mollify-gen emit --format data`, the on-demand cache of mollify::exact).
//
// The format, one record per line, `#` to the end of a line a comment (the
// generator writes each coefficient's exact value there):
//
//   mollify-table 1
//   kernel SPEC dim D support X smoothness S order O parity P has_potential 0|1
//   normalisation X EXACT-TEXT-TO-END-OF-LINE
//   quantity NAME pieces N          (table::QuantityId order, every quantity;
//                                    N = 0 for an absent potential)
//   piece LO HI terms T
//   term BASIS S_POWER VAR EDGE EDGE_LO EDGE_POWER LOW CENTRE CENTRE_LO N
//   c HI LO                          (N lines: coefficient k and its low part)
//   end
//
// Every double is a C99 hexadecimal float (exact both ways), or inf. BASIS
// and VAR are the enumerator names of table::Basis and table::Var.
#pragma once

#include <mollify/table.hpp>

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <string_view>

namespace mollify {

// What a writer may print beside coefficient k of term t of piece p of
// quantity q (the exact value); empty for nothing.
using CoefficientNote = std::function<std::string(int q, int p, int t, int k)>;

// The table as text, every field of it; `banner` lines are written first as
// comments (e.g. the generating command).
std::string write_table(const table::Kernel& k, std::string_view banner = {}, const CoefficientNote& note = {});

// A table read from text; the pointer owns every array the table points to.
// Malformed text is an Error naming `origin`, the line and the bad field.
std::shared_ptr<const table::Kernel> read_table(std::string_view text, std::string_view origin = "table");

// read_table of a file's contents (Error naming the path if unreadable).
std::shared_ptr<const table::Kernel> read_table_file(const std::filesystem::path& path);

// Writes text to path atomically: a temporary file beside it, then rename.
void write_file_atomically(const std::filesystem::path& path, std::string_view text);

}  // namespace mollify
