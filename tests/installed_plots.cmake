# ctest installed_plots: `cmake --install` into a temporary prefix, then the installed
# bin/bivo's `pareto` and `report` write their plots with the source tree's plot scripts out
# of reach: run in a mount namespace (unshare -m) where a tmpfs hides SOURCE_DIR/experiments/plots,
# the path compiled into the binary. Skipped, saying why, without python3 + matplotlib or
# where unshare/mount are not permitted (the test then proves nothing about the source tree).
# -D BUILD_DIR=... -D SOURCE_DIR=... -D WORK_DIR=...
include(${CMAKE_CURRENT_LIST_DIR}/install_test_prefix.cmake)
execute_process(COMMAND /usr/bin/python3 -c "import matplotlib" RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
if(NOT rc EQUAL 0)
  message(STATUS "SKIPPED: /usr/bin/python3 with matplotlib is absent, so bivo cannot plot")
  return()
endif()
set(hidden ${SOURCE_DIR}/experiments/plots)
execute_process(COMMAND unshare -m sh -c "mount -t tmpfs none '${hidden}' && test ! -e '${hidden}/common.py'"
                RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
if(NOT rc EQUAL 0)
  message(STATUS "SKIPPED: cannot hide the source tree here (unshare -m and mount need root or CAP_SYS_ADMIN)")
  return()
endif()
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
set(bivo ${prefix}/bin/bivo)
run(${bivo} synth --category structure_texture_near --frames 3 --fps 2 --supersampling 1 --threads 1
    --output ${WORK_DIR}/seq --name seq_freiburg3)
# `bivo ARGS` with BIVO_PLOTS_DIR unset and the source's plot scripts hidden.
function(run_hidden)
  string(REPLACE ";" " " args "${ARGN}")
  run(${CMAKE_COMMAND} -E env --unset=BIVO_PLOTS_DIR MPLBACKEND=Agg unshare -m sh -c
      "mount -t tmpfs none '${hidden}' && exec '${bivo}' ${args}")
endfunction()
run_hidden(pareto ${WORK_DIR}/seq/seq_freiburg3 --pair 0 --points 3 --levels 2 --level 1 --output ${WORK_DIR}/pareto)
run_hidden(report --sequences ${WORK_DIR}/seq/seq_freiburg3 --methods single --levels 2 --lambda-points 0
           --eps-points 0 --pareto-level 1 --pareto-points 3 --output ${WORK_DIR}/report)
foreach(png pareto/pareto_pair0.png report/images/per_frame_error.png report/images/runtime.png
            report/images/pareto_seq_freiburg3.png)
  if(NOT EXISTS ${WORK_DIR}/${png})
    file(GLOB_RECURSE written RELATIVE ${WORK_DIR} ${WORK_DIR}/pareto/* ${WORK_DIR}/report/*)
    message(FATAL_ERROR "installed bivo did not write ${png} with the source's plot scripts hidden; written: ${written}")
  endif()
endforeach()
# The control: the build tree's bivo, which knows only the source path, cannot plot there.
execute_process(COMMAND ${CMAKE_COMMAND} -E env --unset=BIVO_PLOTS_DIR unshare -m sh -c
                "mount -t tmpfs none '${hidden}' && exec '${BUILD_DIR}/experiments/bivo' pareto '${WORK_DIR}/seq/seq_freiburg3' --pair 0 --points 3 --levels 2 --level 1 --output '${WORK_DIR}/control'"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc EQUAL 0 OR NOT err MATCHES "plot scripts are neither beside bivo")
  message(FATAL_ERROR "the source's plot scripts were not hidden (the build tree's bivo plotted: ${rc} ${err})")
endif()
if(NOT EXISTS ${hidden}/common.py)
  message(FATAL_ERROR "the source tree's plot scripts vanished outside the test's mount namespace")
endif()
file(REMOVE_RECURSE ${WORK_DIR})
message(STATUS "installed_plots: pareto and report plotted from ${prefix}/share/bivo/plots")
