// Tables loaded at run time: a table file written by
// `mollify-gen emit --format data` (format: generator/write_data.cpp) read
// into an object that owns every array and exposes it as the same
// table::Kernel the compiled headers define, so anything that evaluates a
// compiled table evaluates a loaded one. No GMP, no generator.
#pragma once

#include <mollify/table.hpp>

#include <filesystem>
#include <memory>
#include <string>
#include <string_view>

namespace mollify {

class TableFile {
public:
    // Throws Error naming the file, the line and the bad value.
    static TableFile load(const std::filesystem::path& path);
    // The text of a table file; `origin` names it in messages.
    static TableFile parse(const std::string& text, const std::string& origin);

    const table::Kernel& kernel() const;
    // The format version read (1-4). Version 4 files end in a CRC-32 of
    // everything before it, checked on reading: a file changed after
    // mollify-gen wrote it fails to load even where every field is well
    // formed. Versions 1-3 (no checksum) are read as before.
    int version() const;
    // The last line of a version 4 file whose every byte before it is
    // `body`: "checksum crc32 <8 lower-case hex digits>\n", zlib's CRC-32
    // (Python's zlib.crc32). For writers (mollify-gen's, or one's own).
    static std::string checksum_line(std::string_view body);

    TableFile(TableFile&&) noexcept;
    TableFile& operator=(TableFile&&) noexcept;
    ~TableFile();

    struct Storage;  // opaque: the arrays, strings and the table::Kernel pointing into them

private:
    explicit TableFile(std::unique_ptr<Storage> s);
    std::unique_ptr<Storage> s_;  // behind a pointer: table::Kernel points into it, moves keep it in place
};

}  // namespace mollify
