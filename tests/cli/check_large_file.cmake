# A 10 MB model (200000 comment lines and 1999 params, then a mistake on its
# next-to-last line): partc reads all of it and points at the mistake, within
# a minute and without writing an output.
# Usage: cmake -DPARTC=... -DDIR=... -P check_large_file.cmake
file(MAKE_DIRECTORY ${DIR})
set(text "model large\ndim 1\ndomain lo=(0) hi=(1)\n")
string(REPEAT "# a comment line of fifty characters, give or take\n" 100000 comments)
set(lines "")
foreach(k RANGE 1 1999)
  string(APPEND lines "param p${k}: real = ${k}.5   # forty characters of comment here\n")
endforeach()
file(WRITE ${DIR}/large.part "${text}${comments}${comments}${lines}particles P(1) {\n}\nstep {\n  x[i] = 1\n}\n")
file(SIZE ${DIR}/large.part size)
if(size LESS 10000000)
  message(FATAL_ERROR "the file is only ${size} bytes")
endif()
execute_process(COMMAND ${PARTC} ${DIR}/large.part -o ${DIR}/large.cpp
                RESULT_VARIABLE status ERROR_VARIABLE err TIMEOUT 60)
if(NOT status EQUAL 1 OR NOT err MATCHES "large.part:202006:3: error: 'x' is not a variable")
  message(FATAL_ERROR "expected the mistake on the last lines, exit 1; got ${status}:\n${err}")
endif()
if(EXISTS ${DIR}/large.cpp)
  message(FATAL_ERROR "an output was written although the model has an error")
endif()
