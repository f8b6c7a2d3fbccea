# make install / cmake --install (docs/library.md): the tools, libvdbappear with its headers, a CMake
# package (vdbappear::vdbappear), a pkg-config file, man pages made from each tool's --help
# (help2man), bash completion, and the docs.
include(CMakePackageConfigHelpers)
get_property(tools GLOBAL PROPERTY VDBAPPEAR_TOOLS)

# Debian's libopenvdb-tools owns /usr/bin/vdb_render, vdb_print, ...: never install over them.
install(CODE [[
  if(CMAKE_INSTALL_PREFIX STREQUAL "/usr" OR CMAKE_INSTALL_PREFIX STREQUAL "/usr/")
    message(FATAL_ERROR "vdbappear: will not install into /usr, which Debian's packages own (libopenvdb-tools has its own vdb_render there); use /usr/local (the default) or a prefix of your own")
  endif()
]])

install(TARGETS ${tools} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS vdbappear vdbappear_image vdbappear_openvdb EXPORT vdbappearTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
# Loaded by libvdbappear_image from its own folder for formats other than OpenEXR.
install(TARGETS vdbappear_oiio LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(DIRECTORY libvdbappear/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/libvdbappear FILES_MATCHING PATTERN "*.h")
install(FILES ${PROJECT_BINARY_DIR}/libvdbappear/generated/libvdbappear/version.h
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/libvdbappear)

set(package_dir ${CMAKE_INSTALL_LIBDIR}/cmake/vdbappear)
install(EXPORT vdbappearTargets NAMESPACE vdbappear:: DESTINATION ${package_dir})
configure_package_config_file(cmake/vdbappearConfig.cmake.in ${PROJECT_BINARY_DIR}/package/vdbappearConfig.cmake
                              INSTALL_DESTINATION ${package_dir})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/package/vdbappearConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)  # 0.x: a minor version may change the API
install(FILES ${PROJECT_BINARY_DIR}/package/vdbappearConfig.cmake ${PROJECT_BINARY_DIR}/package/vdbappearConfigVersion.cmake
        DESTINATION ${package_dir})
configure_file(cmake/vdbappear.pc.in ${PROJECT_BINARY_DIR}/package/vdbappear.pc.in @ONLY)
# The prefix of `cmake --install --prefix P` is known only at install time.
set(pc_code [[
  file(READ "@PROJECT_BINARY_DIR@/package/vdbappear.pc.in" pc)
  string(REGEX REPLACE "^prefix=[^\n]*" "prefix=${CMAKE_INSTALL_PREFIX}" pc "${pc}")
  set(pc_file "$ENV{DESTDIR}${CMAKE_INSTALL_PREFIX}/@CMAKE_INSTALL_LIBDIR@/pkgconfig/vdbappear.pc")
  message(STATUS "Installing: ${pc_file}")
  file(WRITE "${pc_file}" "${pc}")
]])
string(CONFIGURE "${pc_code}" pc_code @ONLY)
install(CODE "${pc_code}")

# Man pages, made at build time from each tool's --help (so they never disagree with it).
find_program(HELP2MAN help2man)
if(HELP2MAN AND NOT VDBAPPEAR_SANITIZE)
  set(pages "")
  foreach(tool IN LISTS tools)
    set(page ${PROJECT_BINARY_DIR}/man/${tool}.1)
    add_custom_command(OUTPUT ${page}
      COMMAND ${CMAKE_COMMAND} -DTOOL=$<TARGET_FILE:${tool}> -DVERSION=${PROJECT_VERSION} -DHELP2MAN=${HELP2MAN}
              -DOUTPUT=${page} -P ${PROJECT_SOURCE_DIR}/cmake/man_page.cmake
      DEPENDS ${tool} ${PROJECT_SOURCE_DIR}/cmake/man_page.cmake
      COMMENT "Man page ${tool}.1" VERBATIM)
    list(APPEND pages ${page})
  endforeach()
  add_custom_target(man_pages ALL DEPENDS ${pages})
  install(FILES ${pages} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
elseif(NOT HELP2MAN)
  message(WARNING "help2man not found: no man pages (scripts/install-deps.sh installs it)")
endif()

# Bash completion: one file per tool name, where bash-completion looks them up on first use.
list(JOIN tools " " VDBAPPEAR_TOOL_NAMES)
configure_file(tools/completion/vdbappear.bash.in ${PROJECT_BINARY_DIR}/completion/vdbappear.bash @ONLY)
foreach(tool IN LISTS tools)
  install(FILES ${PROJECT_BINARY_DIR}/completion/vdbappear.bash DESTINATION ${CMAKE_INSTALL_DATADIR}/bash-completion/completions
          RENAME ${tool})
endforeach()

install(FILES README.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(DIRECTORY docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR})
