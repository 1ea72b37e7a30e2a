# `cmake --install build [--prefix P]`: the CLI (bin/bivo), the static libraries of every
# layer, the public headers (include/bivo/<layer>/...), a CMake package (find_package(bivo)
# with one imported target per layer, bivo::solvers ... bivo::experiments) and the Python
# module (BIVO_PYTHON_INSTALL_DIR). examples/cpp is an application built against it;
# tests/install_package.cmake installs to a temporary prefix and builds it.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(BIVO_LAYER_TARGETS bivo_geometry bivo_conic bivo_solvers bivo_problems bivo_odometry_io bivo_odometry_synth
    bivo_odometry_kernels bivo_odometry bivo_conic_files bivo_experiments)
foreach(target ${BIVO_LAYER_TARGETS})
  string(REGEX REPLACE "^bivo_" "" export_name ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${export_name})
endforeach()
set_target_properties(bivo_suitesparse PROPERTIES EXPORT_NAME suitesparse)

install(TARGETS ${BIVO_LAYER_TARGETS} bivo_suitesparse EXPORT bivoTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(TARGETS bivo RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# The plot scripts, found by bin/bivo relative to itself (experiments/plotting.cpp), so an
# installed bivo writes plots without the source tree.
install(DIRECTORY ${CMAKE_SOURCE_DIR}/experiments/plots/ DESTINATION ${CMAKE_INSTALL_DATADIR}/bivo/plots
        FILES_MATCHING PATTERN "*.py")
# The public headers: the bi-objective layer, the analytic problems, and the odometry's TUM I/O
# and renderer. The odometry instance and the engines are used through bin/bivo and the Python
# module: their headers expose the per-pixel kernels' buffers (odometry/kernels/), which stay
# private, so they are not installed; nor are test fixtures (tests/support/).
foreach(folder solvers problems odometry/io odometry/synth)
  install(DIRECTORY ${CMAKE_SOURCE_DIR}/${folder}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/bivo/${folder}
          FILES_MATCHING PATTERN "*.h")
endforeach()

set(BIVO_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/bivo)
install(EXPORT bivoTargets NAMESPACE bivo:: DESTINATION ${BIVO_CMAKE_DIR})
configure_package_config_file(${CMAKE_SOURCE_DIR}/cmake/bivoConfig.cmake.in ${CMAKE_BINARY_DIR}/bivoConfig.cmake
                              INSTALL_DESTINATION ${BIVO_CMAKE_DIR})
write_basic_package_version_file(${CMAKE_BINARY_DIR}/bivoConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/bivoConfig.cmake ${CMAKE_BINARY_DIR}/bivoConfigVersion.cmake
        DESTINATION ${BIVO_CMAKE_DIR})

if(BIVO_PYTHON)
  # Debian's layout: /usr/lib/python3/dist-packages for prefix /usr (relative to the prefix).
  set(BIVO_PYTHON_INSTALL_DIR "lib/python3/dist-packages" CACHE STRING "where the Python module goes, relative to the prefix")
  install(TARGETS bivo_python LIBRARY DESTINATION ${BIVO_PYTHON_INSTALL_DIR})
endif()
