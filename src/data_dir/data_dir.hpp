// Where mollify's commands (mollify-gen, mollify) find their data files
// (the transcribed seed tables, the scenes, the checked-in tables); library
// mollify_data_dir, linked by the commands only (the generator builds
// without libmollify, and no library user needs it). An installed executable in
// <prefix>/bin reads <prefix>/share/mollify/NAME, found from its own path
// (/proc/self/exe), so an installed tree works wherever it is moved and
// after the source tree is gone; an executable in the build tree has no such
// folder beside it and reads the source tree's folder it was compiled with.
#pragma once

#include <string>
#include <string_view>

namespace mollify {

// <folder of the executable>/<bin-to-data>/NAME if that folder exists, else
// `build_tree_folder`.
std::string data_dir(std::string_view name, std::string_view build_tree_folder);

}  // namespace mollify
