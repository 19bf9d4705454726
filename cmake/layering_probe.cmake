# The layering tests (CMakeLists.txt, `layering.*`): compiles PROBE, a file that includes HEADER
# (a header of a higher layer, relative to src/), with only the include roots ROOTS (the lower
# layers' roots, separated by |) and passes only when the header exists in the source tree and the
# compiler cannot find it: a wrong-way include fails to build.
#   cmake -DCOMPILER=c++ -DSOURCE_DIR=src -DROOTS=a|b -DPROBE=p.cpp -DHEADER=gridshell/x/y.h -P this
if(NOT EXISTS ${SOURCE_DIR}/${HEADER})
  message(FATAL_ERROR "probe: ${HEADER} is not in ${SOURCE_DIR}: update the probe")
endif()
set(flags -std=c++20 -fsyntax-only)
string(REPLACE "|" ";" ROOTS "${ROOTS}")
foreach(root ${ROOTS})
  list(APPEND flags -I${root})
endforeach()
execute_process(COMMAND ${COMPILER} ${flags} ${PROBE} RESULT_VARIABLE status
                ERROR_VARIABLE err OUTPUT_VARIABLE out)
string(REGEX MATCH "${HEADER}'?(: No such file| file not found)" found "${err}")
if(status EQUAL 0 OR NOT found)
  message(FATAL_ERROR "layering: ${PROBE} was expected to fail to find ${HEADER} with the roots "
                      "${ROOTS}; the compiler said (status ${status}):\n${err}")
endif()
message(STATUS "layering holds: ${HEADER} is out of reach of ${ROOTS}")
