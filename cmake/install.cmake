# What `cmake --install BUILD --prefix P` puts under P (docs/install.md, "Installing"):
#   bin/cmc                              the program
#   lib/libcmc.a, include/cmc/...        the library and its headers (validation's under
#                                        include/cmc/validation)
#   lib/cmake/cmc/                       the CMake package: find_package(cmc), target cmc::cmc
#   lib/python3.X/{dist,site}-packages/cmc   the Python package with its compiled core
#   share/cmc/{cases,reference,reports}  the case files, the stored references and the
#                                        overlay script of `cmc check`
# The installed program and module find share/cmc from where they sit (input/DataDir.hpp),
# so the tree can be moved as a whole.
include(CMakePackageConfigHelpers)

set(CMC_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/cmc CACHE STRING "where the CMake package goes (under the prefix)")

set_target_properties(cmclib PROPERTIES EXPORT_NAME cmc)
install(TARGETS cmc RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(TARGETS cmclib EXPORT cmcTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(DIRECTORY ${CMAKE_SOURCE_DIR}/solver/cmc/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/cmc
        FILES_MATCHING PATTERN "*.hpp" PATTERN "*.cuh")
install(DIRECTORY ${CMAKE_SOURCE_DIR}/validation/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/cmc/validation
        FILES_MATCHING PATTERN "*.hpp")
install(EXPORT cmcTargets NAMESPACE cmc:: DESTINATION ${CMC_INSTALL_CMAKEDIR})
configure_package_config_file(${CMAKE_SOURCE_DIR}/cmake/cmcConfig.cmake.in ${CMAKE_BINARY_DIR}/cmcConfig.cmake
                              INSTALL_DESTINATION ${CMC_INSTALL_CMAKEDIR}
                              PATH_VARS CMAKE_INSTALL_DATADIR)
write_basic_package_version_file(${CMAKE_BINARY_DIR}/cmcConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/cmcConfig.cmake ${CMAKE_BINARY_DIR}/cmcConfigVersion.cmake
        DESTINATION ${CMC_INSTALL_CMAKEDIR})

install(DIRECTORY ${CMAKE_SOURCE_DIR}/cases ${CMAKE_SOURCE_DIR}/reference DESTINATION ${CMAKE_INSTALL_DATADIR}/cmc)
install(FILES ${CMAKE_SOURCE_DIR}/reports/plot_check.py DESTINATION ${CMAKE_INSTALL_DATADIR}/cmc/reports)

# The Python package, where the module was built: Debian's Python reads
# PREFIX/lib/python3.X/dist-packages (for /usr/local), others site-packages.
if(TARGET cmc_python)
  if(Python_SITEARCH MATCHES "dist-packages")
    set(cmc_python_dir lib/python${Python_VERSION_MAJOR}.${Python_VERSION_MINOR}/dist-packages)
  else()
    set(cmc_python_dir lib/python${Python_VERSION_MAJOR}.${Python_VERSION_MINOR}/site-packages)
  endif()
  set(CMC_INSTALL_PYTHONDIR ${cmc_python_dir} CACHE STRING "where the Python package cmc goes (under the prefix)")
  install(DIRECTORY ${CMAKE_SOURCE_DIR}/python/cmc/ DESTINATION ${CMC_INSTALL_PYTHONDIR}/cmc
          FILES_MATCHING PATTERN "*.py" PATTERN "__pycache__" EXCLUDE)
  install(TARGETS cmc_python LIBRARY DESTINATION ${CMC_INSTALL_PYTHONDIR}/cmc)
endif()
