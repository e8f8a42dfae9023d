# `cmake --install`: the relief libraries, their headers, the CLI and a CMake package, so another
# project can `find_package(relief)` and link relief::render (examples/embed/ is such a project).
# Two components, which are also the two Debian packages CPack makes (docs/packaging.md):
#   bin -> relief:     the CLI, its man page (generated from the --help text), the docs
#   dev -> relief-dev: the static libraries, headers and CMake package
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)
# `install` and cpack install what is built and build nothing (not every test and benchmark):
# build the targets first (relief and relief_man for the relief package).
set(CMAKE_SKIP_INSTALL_ALL_DEPENDENCY ON)

set(RELIEF_EXPORTED_LIBS relief_base relief_rasterizer relief_shaders relief_plugins relief_bake relief_scene relief_builtin
    relief_render relief_gl)
foreach(lib IN LISTS RELIEF_EXPORTED_LIBS)
  string(REPLACE "relief_" "" short ${lib})
  set_target_properties(${lib} PROPERTIES EXPORT_NAME ${short})
endforeach()

install(TARGETS ${RELIEF_EXPORTED_LIBS} EXPORT reliefTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT dev)
install(TARGETS relief RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT bin)
# Headers keep their folder so `#include "render/render.h"` reads the same inside and outside;
# a folder's *_internal.h headers are its own (scene/gltf_internal.h) and stay out.
foreach(dir base rasterizer shaders_cpp plugins bake scene builtin render gl)
  install(DIRECTORY ${CMAKE_SOURCE_DIR}/${dir}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/relief/${dir}
          COMPONENT dev FILES_MATCHING PATTERN "*.h" PATTERN "*_internal.h" EXCLUDE)
endforeach()

install(EXPORT reliefTargets NAMESPACE relief:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/relief
        COMPONENT dev)
configure_package_config_file(${CMAKE_SOURCE_DIR}/cmake/reliefConfig.cmake.in
  ${CMAKE_BINARY_DIR}/reliefConfig.cmake INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/relief)
write_basic_package_version_file(${CMAKE_BINARY_DIR}/reliefConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/reliefConfig.cmake ${CMAKE_BINARY_DIR}/reliefConfigVersion.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/relief COMPONENT dev)

# relief.1: `relief --help` and every subcommand's --help, made from the built binary
# (scripts/relief-man.sh). Part of `all`; OPTIONAL so that installing after building only the
# relief target still works (the package test checks the page is in the .deb).
set(RELIEF_MAN_PAGE ${CMAKE_BINARY_DIR}/man/relief.1.gz)
add_custom_command(OUTPUT ${RELIEF_MAN_PAGE}
  COMMAND bash ${CMAKE_SOURCE_DIR}/scripts/relief-man.sh $<TARGET_FILE:relief> ${PROJECT_VERSION}
          ${RELIEF_MAN_PAGE}
  DEPENDS relief ${CMAKE_SOURCE_DIR}/scripts/relief-man.sh
  COMMENT "Generating man/relief.1.gz from relief --help" VERBATIM)
add_custom_target(relief_man ALL DEPENDS ${RELIEF_MAN_PAGE})
install(FILES ${RELIEF_MAN_PAGE} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1 COMPONENT bin OPTIONAL)

file(GLOB relief_doc_files CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/docs/*.md ${CMAKE_SOURCE_DIR}/docs/*.json)
install(FILES ${CMAKE_SOURCE_DIR}/README.md ${relief_doc_files}
        DESTINATION ${CMAKE_INSTALL_DOCDIR} COMPONENT bin)
install(PROGRAMS ${CMAKE_SOURCE_DIR}/examples/slurm/render-array.sh
        DESTINATION ${CMAKE_INSTALL_DOCDIR}/examples/slurm COMPONENT bin)

# Debian packages: `cmake --build build --target package` (all targets), or, after building the
# relief and relief_man targets only, `cd build && cpack -G DEB` (scripts/package-test.sh).
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME relief)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_VENDOR relief)
set(CPACK_PACKAGE_CONTACT "relief developers <relief@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "per-fragment displacement (relief) mapping renderer")
set(CPACK_PACKAGE_DESCRIPTION
    "A headless renderer for relief mapping: a multithreaded CPU rasterizer with C++ shader\nplugins and an OpenGL 4.5 backend through EGL running GLSL twins of the same plugins.")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_COMPONENTS_ALL bin dev)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_HOMEPAGE "https://example.invalid/relief")
set(CPACK_DEBIAN_BIN_PACKAGE_NAME relief)
set(CPACK_DEBIAN_BIN_PACKAGE_SECTION graphics)
set(CPACK_DEBIAN_BIN_PACKAGE_SHLIBDEPS ON)  # Depends from dpkg-shlibdeps on the binary
set(CPACK_DEBIAN_DEV_PACKAGE_NAME relief-dev)
set(CPACK_DEBIAN_DEV_PACKAGE_SECTION libdevel)
# The static libraries link these privately; reliefConfig.cmake finds them again.
set(relief_dev_depends "libglm-dev, libhwy-dev, libopenimageio-dev, libtinygltf-dev, nlohmann-json3-dev, libmeshoptimizer-dev, libdraco-dev, pkg-config")
if(RELIEF_GL)
  string(APPEND relief_dev_depends ", libepoxy-dev, libegl-dev")
  # libepoxy opens libEGL at run time, so dpkg-shlibdeps cannot see the GL backend's drivers.
  set(CPACK_DEBIAN_BIN_PACKAGE_RECOMMENDS "libegl1, libegl-mesa0, libgl1-mesa-dri")
endif()
set(CPACK_DEBIAN_DEV_PACKAGE_DEPENDS "${relief_dev_depends}")
set(CPACK_COMPONENT_BIN_DESCRIPTION "${CPACK_PACKAGE_DESCRIPTION_SUMMARY}: the relief command line")
set(CPACK_COMPONENT_DEV_DESCRIPTION
    "${CPACK_PACKAGE_DESCRIPTION_SUMMARY}: static libraries, headers and CMake package")
include(CPack)
