# FFTW3, GMP and MPFR as imported targets mollify::fftw3, mollify::gmp and
# mollify::mpfr. Debian ships no usable CMake package for them (fftw3's
# FFTW3Config.cmake names a FFTW3LibraryDepends.cmake it does not install),
# so the build and the installed package (mollifyConfig.cmake) both find
# them here: the exported targets then name these targets, never a path of
# the machine that built them.
function(mollify_import_library target header library)
  if(TARGET ${target})
    return()
  endif()
  string(MAKE_C_IDENTIFIER "MOLLIFY_${library}" var)
  find_path(${var}_INCLUDE_DIR ${header})
  find_library(${var}_LIBRARY ${library})
  if(NOT ${var}_INCLUDE_DIR OR NOT ${var}_LIBRARY)
    set(MOLLIFY_IMPORT_MISSING "${MOLLIFY_IMPORT_MISSING};${library} (${header})" PARENT_SCOPE)
    return()
  endif()
  add_library(${target} UNKNOWN IMPORTED)
  set_target_properties(${target} PROPERTIES
    IMPORTED_LOCATION "${${var}_LIBRARY}"
    INTERFACE_INCLUDE_DIRECTORIES "${${var}_INCLUDE_DIR}")
endfunction()
