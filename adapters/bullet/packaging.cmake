# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
# libselfcol_bullet's packaging, included at the end of CMakeLists.txt (once
# the target selfcol_bullet exists), as lib/CMakeLists.txt does it for
# libselfcol: the exported-symbol test, and (SELFCOL_INSTALL) the install of
# the library, its header, the package component "bullet" (the export set
# selfcolBulletTargets, loaded by selfcolConfig.cmake for
# find_package(selfcol COMPONENTS bullet)) and selfcol_bullet.pc.
# libselfcol_bullet follows BUILD_SHARED_LIBS as libselfcol does: one install
# prefix holds one flavour of both.
get_target_property(SELFCOL_BULLET_LIBRARY_TYPE selfcol_bullet TYPE)

# The shared library exports exactly the SELFCOL_BULLET_API declarations of
# bullet.h, which are exactly libselfcol_bullet.map's names (the header test,
# C99 and C++11 without Bullet, is in tests/CMakeLists.txt).
if(SELFCOL_BUILD_TESTS AND SELFCOL_BULLET_LIBRARY_TYPE STREQUAL "SHARED_LIBRARY")
  add_test(NAME bullet_exported_symbols
    COMMAND sh ${PROJECT_SOURCE_DIR}/tests/check_exports.sh $<TARGET_FILE:selfcol_bullet>
      ${CMAKE_CURRENT_SOURCE_DIR}/include/selfcol ${CMAKE_CURRENT_SOURCE_DIR}/libselfcol_bullet.map
      SELFCOL_BULLET_API selfcol_bullet_)
endif()

# A static libselfcol_bullet carries Bullet in its link interface. CMake writes
# what CMakeLists.txt links (pkg-config's absolute library paths) into it, and
# install(EXPORT) would copy them into the package. They are replaced by the
# imported target PkgConfig::SELFCOL_BULLET_DEP (the same libraries), which
# the installed package recreates with pkg-config, as libselfcol's
# PkgConfig::SELFCOL_CCD: no path of this machine's Bullet is exported.
if(SELFCOL_BULLET_LIBRARY_TYPE STREQUAL "STATIC_LIBRARY" AND TARGET PkgConfig::SELFCOL_BULLET_DEP)
  get_target_property(_selfcol_bullet_interface selfcol_bullet INTERFACE_LINK_LIBRARIES)
  set(_selfcol_bullet_kept "")
  foreach(_selfcol_bullet_item IN LISTS _selfcol_bullet_interface)
    # A file path is listed as is (CMake 3.25), a name may be in $<LINK_ONLY:>.
    set(_selfcol_bullet_path "${_selfcol_bullet_item}")
    if(_selfcol_bullet_item MATCHES "^\\$<LINK_ONLY:(.*)>$")
      set(_selfcol_bullet_path "${CMAKE_MATCH_1}")
    endif()
    if(NOT _selfcol_bullet_path IN_LIST SELFCOL_BULLET_DEP_LINK_LIBRARIES)
      list(APPEND _selfcol_bullet_kept "${_selfcol_bullet_item}")
    endif()
  endforeach()
  list(APPEND _selfcol_bullet_kept "$<LINK_ONLY:PkgConfig::SELFCOL_BULLET_DEP>")
  set_property(TARGET selfcol_bullet PROPERTY INTERFACE_LINK_LIBRARIES "${_selfcol_bullet_kept}")
  unset(_selfcol_bullet_interface)
  unset(_selfcol_bullet_kept)
  unset(_selfcol_bullet_item)
  unset(_selfcol_bullet_path)
endif()

if(SELFCOL_INSTALL)
  install(TARGETS selfcol_bullet EXPORT selfcolBulletTargets
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  install(FILES ${CMAKE_CURRENT_SOURCE_DIR}/include/selfcol/bullet.h
    DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/selfcol)
  # Loaded by selfcolConfig.cmake for find_package(selfcol COMPONENTS bullet),
  # which finds Bullet (pkg-config) first for a static library.
  install(EXPORT selfcolBulletTargets NAMESPACE selfcol:: DESTINATION ${SELFCOL_INSTALL_CMAKEDIR})

  # selfcol_bullet.pc, its prefix written at install time as selfcol.pc's.
  # Requires selfcol (its Cflags: -DSELFCOL_STATIC for a static install);
  # Requires.private bullet and Libs.private the C++ runtime, which
  # `pkg-config --static --libs selfcol_bullet` adds for a static link by a C
  # compiler driver. Code that calls Bullet itself asks for bullet too.
  set(SELFCOL_BULLET_PC_PREFIX "@SELFCOL_BULLET_PC_PREFIX@") # left for the install step
  foreach(_dir LIBDIR INCLUDEDIR)
    if(IS_ABSOLUTE "${CMAKE_INSTALL_${_dir}}")
      set(SELFCOL_BULLET_PC_${_dir} "${CMAKE_INSTALL_${_dir}}")
    else()
      set(SELFCOL_BULLET_PC_${_dir} "\${prefix}/${CMAKE_INSTALL_${_dir}}")
    endif()
  endforeach()
  # The C++ runtime: what a C++ link adds to a C link (GCC: -lstdc++ -lm).
  set(_selfcol_bullet_cxx_libs "")
  foreach(_lib IN LISTS CMAKE_CXX_IMPLICIT_LINK_LIBRARIES)
    if(NOT _lib IN_LIST CMAKE_C_IMPLICIT_LINK_LIBRARIES)
      list(APPEND _selfcol_bullet_cxx_libs "-l${_lib}")
    endif()
  endforeach()
  list(REMOVE_DUPLICATES _selfcol_bullet_cxx_libs)
  list(JOIN _selfcol_bullet_cxx_libs " " SELFCOL_BULLET_PC_CXX_LIBS)
  configure_file(${CMAKE_CURRENT_SOURCE_DIR}/selfcol_bullet.pc.in
    ${CMAKE_CURRENT_BINARY_DIR}/selfcol_bullet.pc.in @ONLY)
  install(CODE "set(_selfcol_bullet_pc_dir \"${CMAKE_CURRENT_BINARY_DIR}\")")
  install(CODE [[
    file(READ "${_selfcol_bullet_pc_dir}/selfcol_bullet.pc.in" _selfcol_bullet_pc)
    string(REPLACE "@SELFCOL_BULLET_PC_PREFIX@" "${CMAKE_INSTALL_PREFIX}" _selfcol_bullet_pc
      "${_selfcol_bullet_pc}")
    file(WRITE "${_selfcol_bullet_pc_dir}/selfcol_bullet.pc" "${_selfcol_bullet_pc}")
  ]])
  install(FILES ${CMAKE_CURRENT_BINARY_DIR}/selfcol_bullet.pc
    DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
endif()
