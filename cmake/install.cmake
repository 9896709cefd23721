# cmake --install: headers and tables, libmollify and the exact library, the
# commands, their data, a relocatable CMake package (find_package(mollify):
# mollify::mollify, mollify::exact) and pkg-config files (mollify,
# mollify-exact). By directory, so that headers and tables added later are
# installed without a change here; generated/src (compiled into libmollify)
# is not installed.
include(CMakePackageConfigHelpers)

set(MOLLIFY_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/mollify)
set(MOLLIFY_INSTALL_DATADIR ${CMAKE_INSTALL_DATADIR}/mollify)

# <prefix>/include/mollify/: the runtime's headers and the emitted tables.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/mollify ${PROJECT_SOURCE_DIR}/generated/mollify
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} FILES_MATCHING PATTERN "*.hpp")
# <prefix>/include/mollify/exact/: the exact generator's headers (mollify::exact).
install(DIRECTORY ${PROJECT_SOURCE_DIR}/generator/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/mollify/exact
        FILES_MATCHING PATTERN "*.hpp" PATTERN transcriptions EXCLUDE)

install(TARGETS mollify_base mollify mollify_generator mollify_exact EXPORT mollifyTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(EXPORT mollifyTargets NAMESPACE mollify:: DESTINATION ${MOLLIFY_INSTALL_CMAKEDIR})

# The commands, and what they read at run time (mollify::data_dir finds
# <bin>/../share/mollify/NAME): mollify-gen errata the transcriptions,
# mollify run/list the scenes, mollify report the checked-in generated/ to
# compare a fresh emit with (below). The mollify command (target mollify-cli) is
# OPTIONAL: installed when built.
install(TARGETS mollify-gen RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS mollify-cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} OPTIONAL)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/generator/transcriptions ${PROJECT_SOURCE_DIR}/scenes
        DESTINATION ${MOLLIFY_INSTALL_DATADIR})
# All of generated/ (what `mollify-gen emit` writes) as checked in, for
# `mollify report` to compare a fresh emit with.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/generated/ DESTINATION ${MOLLIFY_INSTALL_DATADIR}/generated)

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/mollifyConfig.cmake.in
  ${PROJECT_BINARY_DIR}/mollifyConfig.cmake INSTALL_DESTINATION ${MOLLIFY_INSTALL_CMAKEDIR})
# 0.x: no compatibility promised across minor versions.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/mollifyConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/mollifyConfig.cmake ${PROJECT_BINARY_DIR}/mollifyConfigVersion.cmake
        DESTINATION ${MOLLIFY_INSTALL_CMAKEDIR})

# pkg-config: prefix relative to the .pc file's folder (${pcfiledir}), so the
# installed tree can move.
file(RELATIVE_PATH MOLLIFY_PC_TO_PREFIX /${CMAKE_INSTALL_LIBDIR}/pkgconfig /)
string(REGEX REPLACE "/$" "" MOLLIFY_PC_TO_PREFIX "${MOLLIFY_PC_TO_PREFIX}")
foreach(pc IN ITEMS mollify mollify-exact)
  configure_file(${PROJECT_SOURCE_DIR}/cmake/${pc}.pc.in ${PROJECT_BINARY_DIR}/${pc}.pc @ONLY)
  install(FILES ${PROJECT_BINARY_DIR}/${pc}.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
endforeach()
