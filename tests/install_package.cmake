# ctest install_package: `cmake --install` into a temporary prefix, then examples/cpp built
# against it with find_package(bivo) and run, and the installed Python module imported.
# -D BUILD_DIR=... -D SOURCE_DIR=... -D WORK_DIR=... -D PYTHON=... -D CXX=... -D CXX_FLAGS=... -D LINKER_FLAGS=...
include(${CMAKE_CURRENT_LIST_DIR}/install_test_prefix.cmake)
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
foreach(f bin/bivo lib/cmake/bivo/bivoConfig.cmake include/bivo/solvers/outer_loop.h include/bivo/odometry/io/tum_dataset.h)
  if(NOT EXISTS ${prefix}/${f})
    message(FATAL_ERROR "not installed: ${f}")
  endif()
endforeach()
# Internal headers stay private: the kernels, their pools and lanes, and test fixtures.
file(GLOB_RECURSE installed_headers RELATIVE ${prefix}/include/bivo ${prefix}/include/bivo/*.h)
foreach(h ${installed_headers})
  if(h MATCHES "kernels/|pooled_floats|simd_lanes|parallel_chunks|synthetic_qcqp|support/")
    message(FATAL_ERROR "internal header installed: ${h}")
  endif()
  # Every installed header must compile on its own: none may include one that is not installed.
  file(STRINGS ${prefix}/include/bivo/${h} includes REGEX "^#include \"")
  foreach(line ${includes})
    string(REGEX REPLACE "^#include \"([^\"]+)\".*" "\\1" inc "${line}")
    if(NOT EXISTS ${prefix}/include/bivo/${inc})
      message(FATAL_ERROR "installed header ${h} includes ${inc}, which is not installed")
    endif()
  endforeach()
endforeach()
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/examples/cpp -B ${WORK_DIR}/example -G Ninja -DCMAKE_BUILD_TYPE=Release
    -DCMAKE_PREFIX_PATH=${prefix} "-DCMAKE_CXX_COMPILER=${CXX}" "-DCMAKE_CXX_FLAGS=${CXX_FLAGS}"
    "-DCMAKE_EXE_LINKER_FLAGS=${LINKER_FLAGS}")
run(${CMAKE_COMMAND} --build ${WORK_DIR}/example)
run(${WORK_DIR}/example/pareto_example)
if(NOT last_output MATCHES "knee [0-9]+ of 7 points")
  message(FATAL_ERROR "unexpected output of pareto_example:\n${last_output}")
endif()
run(${prefix}/bin/bivo --help)
# Plots from the installed scripts (share/bivo/plots, found beside bin/bivo), not the source
# tree's: the installed common.py is made to leave a mark, and the plot must be written.
if(EXISTS /usr/bin/python3)
  file(APPEND ${prefix}/share/bivo/plots/common.py
       "\nif os.environ.get('BIVO_INSTALL_MARK'):\n    open(os.environ['BIVO_INSTALL_MARK'], 'w').close()\n")
  run(${prefix}/bin/bivo synth --category structure_texture_near --frames 3 --supersampling 1
      --output ${WORK_DIR}/seq)
  file(GLOB seq_dir ${WORK_DIR}/seq/*)
  run(${CMAKE_COMMAND} -E env BIVO_INSTALL_MARK=${WORK_DIR}/mark ${prefix}/bin/bivo pareto ${seq_dir} --pair 0
      --points 3 --levels 2 --level 1 --output ${WORK_DIR}/pareto)
  if(NOT EXISTS ${WORK_DIR}/mark OR NOT EXISTS ${WORK_DIR}/pareto/pareto_pair0.png)
    message(FATAL_ERROR "installed bivo pareto did not plot with the installed scripts")
  endif()
endif()
if(PYTHON)
  # (no semicolons: they would split the argument list)
  run(${CMAKE_COMMAND} -E env PYTHONPATH=${prefix}/lib/python3/dist-packages ${PYTHON} -c
      "import bivo\nprint(bivo.__file__ if 'gn' in [b['name'] for b in bivo.backends()] else 'no backends')")
  if(NOT last_output MATCHES "^${prefix}")
    message(FATAL_ERROR "imported bivo from ${last_output}, not from the install prefix")
  endif()
endif()
file(REMOVE_RECURSE ${WORK_DIR})
message(STATUS "install_package: installed, example built and run, Python module imported")
