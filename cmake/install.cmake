# Installation under GNUInstallDirs, the CMake package (gonioConfig.cmake, components core
# and render), the pkg-config files and the Debian package (cpack -G DEB).
# SPDX-License-Identifier: MIT
include(CMakePackageConfigHelpers)

set(GONIO_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/gonio)

# One export set per component, so that `COMPONENTS core` loads nothing that names a
# renderer dependency.
install(TARGETS gonio EXPORT gonioCoreTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(EXPORT gonioCoreTargets NAMESPACE gonio:: DESTINATION ${GONIO_CMAKE_DIR}
  FILE gonio-core-targets.cmake)
if(GONIO_BUILD_RENDERER)
  install(TARGETS gonio_render EXPORT gonioRenderTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  install(EXPORT gonioRenderTargets NAMESPACE gonio:: DESTINATION ${GONIO_CMAKE_DIR}
    FILE gonio-render-targets.cmake)
endif()
install(TARGETS gonio_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})

# gonio_fit is linked into the tool only (a static library, Ceres private): its headers
# would declare a library that is not installed.
set(GONIO_HEADER_EXCLUDES PATTERN fit EXCLUDE)
if(NOT GONIO_BUILD_RENDERER)
  list(APPEND GONIO_HEADER_EXCLUDES PATTERN render EXCLUDE)
endif()
install(DIRECTORY include/gonio DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} ${GONIO_HEADER_EXCLUDES})
install(FILES ${GONIO_GENERATED_INCLUDE}/gonio/version.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/gonio)

# The tool needs no file at run time (albedo tables, metal constants and the default scene
# are compiled in); the measured data they come from and the example scenes are installed
# for users to read and render.
install(DIRECTORY data/metals DESTINATION ${CMAKE_INSTALL_DATADIR}/gonio)
install(DIRECTORY scenes/ DESTINATION ${CMAKE_INSTALL_DATADIR}/gonio/scenes)
install(FILES README.md LICENSE NOTICE CHANGELOG.md docs/spec.md docs/materials.md docs/cli.md
        DESTINATION ${CMAKE_INSTALL_DOCDIR})

# --- CMake package ----------------------------------------------------------------------
configure_package_config_file(cmake/gonioConfig.cmake.in
  ${CMAKE_BINARY_DIR}/gonioConfig.cmake INSTALL_DESTINATION ${GONIO_CMAKE_DIR})
# 0.x: a new minor version may change the API, so 0.2 accepts 0.2.* only.
write_basic_package_version_file(${CMAKE_BINARY_DIR}/gonioConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/gonioConfig.cmake ${CMAKE_BINARY_DIR}/gonioConfigVersion.cmake
  DESTINATION ${GONIO_CMAKE_DIR})

# --- pkg-config -------------------------------------------------------------------------
# The prefix is computed from the .pc file's own place (${pcfiledir}), so an install moved
# or made with `cmake --install --prefix P` stays correct.
set(GONIO_PC_DIR ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
file(RELATIVE_PATH GONIO_PC_TO_PREFIX /p/${GONIO_PC_DIR} /p)
string(REGEX REPLACE "/$" "" GONIO_PC_TO_PREFIX "${GONIO_PC_TO_PREFIX}")
# A static libgonio_render needs its dependencies on every link line; a shared one only
# with --static. Embree 3 ships no .pc file, hence -lembree3.
set(GONIO_PC_RENDER_REQUIRES "gonio = ${PROJECT_VERSION}")
set(GONIO_PC_RENDER_LIBS "-lgonio_render")
set(GONIO_PC_RENDER_REQUIRES_PRIVATE "tbb OpenEXR libpng tinyobjloader OpenImageIO tinygltf")
set(GONIO_PC_RENDER_LIBS_PRIVATE "-lembree3")
if(NOT BUILD_SHARED_LIBS)
  string(APPEND GONIO_PC_RENDER_REQUIRES ", ${GONIO_PC_RENDER_REQUIRES_PRIVATE}")
  string(APPEND GONIO_PC_RENDER_LIBS " ${GONIO_PC_RENDER_LIBS_PRIVATE}")
  set(GONIO_PC_RENDER_REQUIRES_PRIVATE "")
  set(GONIO_PC_RENDER_LIBS_PRIVATE "")
endif()
# pugixml (MaterialX documents) is private to libgonio: on every link line of a static
# library, with --static only for a shared one.
if(BUILD_SHARED_LIBS)
  set(GONIO_PC_CORE_REQUIRES "")
  set(GONIO_PC_CORE_REQUIRES_PRIVATE "pugixml")
else()
  set(GONIO_PC_CORE_REQUIRES ", pugixml")
  set(GONIO_PC_CORE_REQUIRES_PRIVATE "")
endif()
configure_file(cmake/gonio.pc.in ${CMAKE_BINARY_DIR}/gonio.pc @ONLY)
install(FILES ${CMAKE_BINARY_DIR}/gonio.pc DESTINATION ${GONIO_PC_DIR})
if(GONIO_BUILD_RENDERER)
  configure_file(cmake/gonio-render.pc.in ${CMAKE_BINARY_DIR}/gonio-render.pc @ONLY)
  install(FILES ${CMAKE_BINARY_DIR}/gonio-render.pc DESTINATION ${GONIO_PC_DIR})
endif()

# --- Debian package: cpack -G DEB in the build directory --------------------------------
set(CPACK_PACKAGE_NAME gonio)
set(CPACK_PACKAGE_VENDOR "the gonio authors")
set(CPACK_PACKAGE_CONTACT "the gonio authors")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "${PROJECT_DESCRIPTION}")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_RESOURCE_FILE_LICENSE ${PROJECT_SOURCE_DIR}/LICENSE)
set(CPACK_RESOURCE_FILE_README ${PROJECT_SOURCE_DIR}/README.md)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
# Depends comes from dpkg-shlibdeps on the installed binaries and libraries (dpkg-dev).
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# The headers include nlohmann/json.hpp; only a user who compiles against gonio needs it.
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "nlohmann-json3-dev")
set(CPACK_GENERATOR DEB)
include(CPack)
