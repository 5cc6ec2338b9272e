# Installs the python component into PREFIX and imports the package from there with a clean PYTHONPATH: the
# installed package must be complete on its own (module, pure-Python part, stubs).
file(REMOVE_RECURSE ${PREFIX})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BINARY_DIR} --component python --prefix ${PREFIX}
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cmake --install --component python failed (${rc})")
endif()
foreach(f __init__.py _rfidray.pyi py.typed)
  if(NOT EXISTS ${PREFIX}/${SITE}/rfidray/${f})
    message(FATAL_ERROR "not installed: ${SITE}/rfidray/${f}")
  endif()
endforeach()
set(ENV{PYTHONPATH} ${PREFIX}/${SITE})
execute_process(COMMAND ${PYTHON} -c
                "import rfidray, os; assert rfidray.__file__.startswith(os.environ['PYTHONPATH']), rfidray.__file__; h = rfidray.Channel(None, 'ideal').one_way([0, 0, 0], [[2.0, 0, 0]]); lam = 299792458.0 / 865.7e6; assert abs(abs(h[0]) - lam / (8 * 3.141592653589793)) < 1e-12, h; print(abs(h[0]))"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "import of the installed package failed:\n${out}${err}")
endif()
message(STATUS "installed package imports; |h| at 2 m (free space, λ/8π) = ${out}")
