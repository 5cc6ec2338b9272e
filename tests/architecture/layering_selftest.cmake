# The layering check must fail when a forbidden include is added: copy the tree's sources to a scratch folder,
# plant one (localization → io, core → cli, bench → cli, raytrace → localization, python → cli, io → python,
# planning → io in turn) and expect check_layering.cmake to fail naming the file; the unmodified copy must pass.
# Usage: cmake -DSOURCE=<tree> -DSCRATCH=<dir> -DCHECK=<check_layering.cmake> -P layering_selftest.cmake
file(REMOVE_RECURSE ${SCRATCH})
foreach(module core raytrace localization planning io adapters bench cli python)
  if(EXISTS ${SOURCE}/${module})
    file(COPY ${SOURCE}/${module} DESTINATION ${SCRATCH} FILES_MATCHING PATTERN "*.h" PATTERN "*.cpp")
  endif()
endforeach()

execute_process(COMMAND ${CMAKE_COMMAND} -DROOT=${SCRATCH} -P ${CHECK} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the unmodified tree should pass the layering check:\n${out}${err}")
endif()

foreach(plant "localization/planted.h|io/scenario_yaml.h" "core/planted.h|cli/commands.h" "bench/planted.h|cli/commands.h"
              "raytrace/planted.h|localization/result.h" "python/planted.h|cli/commands.h" "io/planted.h|python/bindings/bindings.h"
              "planning/planted.h|io/scenario_yaml.h")
  string(REPLACE "|" ";" parts "${plant}")
  list(GET parts 0 file)
  list(GET parts 1 inc)
  file(WRITE ${SCRATCH}/${file} "#pragma once\n#include \"${inc}\"\n")
  execute_process(COMMAND ${CMAKE_COMMAND} -DROOT=${SCRATCH} -P ${CHECK} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(rc EQUAL 0)
    message(FATAL_ERROR "the layering check passed a tree where ${file} includes ${inc}")
  endif()
  string(FIND "${out}${err}" "${file}: #include \"${inc}\"" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "the layering check failed without naming ${file}:\n${out}${err}")
  endif()
  file(REMOVE ${SCRATCH}/${file})
endforeach()
message(STATUS "layering self-test: 6 planted includes detected, the clean tree passes")
