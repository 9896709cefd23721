# Writes OUT: one C++ initialiser {"NAME.toml", R"(...)"} per scene file of
# SCENES ('|'-separated; NAME relative to BASE, e.g. "report/franz_line.toml"),
# compiled into mollify as the report's embedded default scenes
# (tools/mollify/report.cpp). Run by CMake at build time:
#   cmake -DOUT=report_scenes.inc -DBASE=scenes -DSCENES="a.toml|b.toml" -P embed_scenes.cmake
string(REPLACE "|" ";" files "${SCENES}")
set(content "// Generated from scenes/report/*.toml by tools/mollify/embed_scenes.cmake; do not edit.\n")
foreach(f IN LISTS files)
  file(READ "${f}" text)
  if(text MATCHES "\\)mollify_scene\"")
    message(FATAL_ERROR "${f} contains the raw-string delimiter )mollify_scene\"")
  endif()
  file(RELATIVE_PATH name "${BASE}" "${f}")
  string(APPEND content "{\"${name}\", R\"mollify_scene(${text})mollify_scene\"},\n")
endforeach()
file(WRITE "${OUT}.tmp" "${content}")
file(COPY_FILE "${OUT}.tmp" "${OUT}" ONLY_IF_DIFFERENT)
file(REMOVE "${OUT}.tmp")
