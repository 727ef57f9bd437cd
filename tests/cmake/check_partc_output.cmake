# Runs partc on one .part file and compares what it prints with a golden file.
#
#   cmake -DPARTC=... -DPART=dir/name.part -DEXPECTED=dir/name.expected
#         -DMODE=cpp|diagnostic -DWORK=scratch-dir -P check_partc_output.cmake
#
# MODE=cpp: partc must succeed; the emitted C++ must equal EXPECTED.
# MODE=diagnostic: partc must fail with exit status 1, write no output file,
#   and print exactly EXPECTED on stderr.
# MODE=warning: partc must succeed and print exactly EXPECTED on stderr.
# With the environment variable PARTC_UPDATE_GOLDEN=1 the golden file is
# rewritten from what partc printed (then review the diff before committing).
get_filename_component(dir ${PART} DIRECTORY)
get_filename_component(name ${PART} NAME)
get_filename_component(stem ${PART} NAME_WE)
file(MAKE_DIRECTORY ${WORK})
set(out ${WORK}/${name}.cpp)
file(REMOVE ${out})
execute_process(COMMAND ${PARTC} ${name} -o ${out}
                WORKING_DIRECTORY ${dir}
                RESULT_VARIABLE status
                ERROR_VARIABLE stderr)

if(MODE STREQUAL "diagnostic")
  if(NOT status EQUAL 1)
    message(FATAL_ERROR "partc ${name}: expected exit status 1, got '${status}'\n${stderr}")
  endif()
  if(EXISTS ${out})
    message(FATAL_ERROR "partc ${name}: failed but left an output file behind")
  endif()
  set(actual "${stderr}")
elseif(MODE STREQUAL "warning")
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "partc ${name}: failed with status ${status}\n${stderr}")
  endif()
  set(actual "${stderr}")
else()
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "partc ${name}: failed with status ${status}\n${stderr}")
  endif()
  file(READ ${out} actual)
endif()

if("$ENV{PARTC_UPDATE_GOLDEN}" STREQUAL "1")
  file(WRITE ${EXPECTED} "${actual}")
  message(STATUS "updated ${EXPECTED}")
  return()
endif()
file(READ ${EXPECTED} expected)
if(NOT actual STREQUAL expected)
  file(WRITE ${WORK}/${name}.actual "${actual}")
  execute_process(COMMAND diff -u ${EXPECTED} ${WORK}/${name}.actual OUTPUT_VARIABLE difference)
  message(FATAL_ERROR "partc ${name}: output differs from ${EXPECTED}\n${difference}\n"
                      "(if the change is intended: PARTC_UPDATE_GOLDEN=1 ctest -R ${stem}, then review the diff)")
endif()
