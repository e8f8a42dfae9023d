# `cmake --install`: the relief libraries, their headers, the CLI and a CMake package, so another
# project can `find_package(relief)` and link relief::render (examples/embed/ is such a project).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(RELIEF_EXPORTED_LIBS relief_rasterizer relief_shaders relief_plugins relief_bake relief_scene
    relief_render relief_gl)
foreach(lib IN LISTS RELIEF_EXPORTED_LIBS)
  string(REPLACE "relief_" "" short ${lib})
  set_target_properties(${lib} PROPERTIES EXPORT_NAME ${short})
endforeach()

install(TARGETS ${RELIEF_EXPORTED_LIBS} EXPORT reliefTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(TARGETS relief RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# Headers keep their folder so `#include "render/render.h"` reads the same inside and outside.
foreach(dir rasterizer shaders_cpp plugins bake scene render gl)
  install(DIRECTORY ${CMAKE_SOURCE_DIR}/${dir}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/relief/${dir}
          FILES_MATCHING PATTERN "*.h")
endforeach()

install(EXPORT reliefTargets NAMESPACE relief:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/relief)
configure_package_config_file(${CMAKE_SOURCE_DIR}/cmake/reliefConfig.cmake.in
  ${CMAKE_BINARY_DIR}/reliefConfig.cmake INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/relief)
write_basic_package_version_file(${CMAKE_BINARY_DIR}/reliefConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/reliefConfig.cmake ${CMAKE_BINARY_DIR}/reliefConfigVersion.cmake
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/relief)
