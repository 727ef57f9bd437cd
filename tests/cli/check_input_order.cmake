# Results do not depend on the order of the input rows: the md example run
# from its initial state, and from the same rows reversed, ends bitwise equal
# (sums within a cell run in storage order, which loading makes id order).
# Usage: cmake -DPROGRAM=md -DDIR=... -P check_input_order.cmake
include(${CMAKE_CURRENT_LIST_DIR}/../cmake/program_run.cmake)
run(--set N=2000 --steps 0 --seed 3 --output ${DIR}/start.csv)
file(STRINGS ${DIR}/start.csv lines)
list(POP_FRONT lines header)
list(REVERSE lines)
list(PREPEND lines "${header}")
list(JOIN lines "\n" reversed)
file(WRITE ${DIR}/reversed.csv "${reversed}\n")
run(--set N=2000 --steps 30 --input ${DIR}/start.csv --output ${DIR}/from_start.csv)
run(--set N=2000 --steps 30 --input ${DIR}/reversed.csv --output ${DIR}/from_reversed.csv)
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${DIR}/from_start.csv
                        ${DIR}/from_reversed.csv RESULT_VARIABLE different)
if(different)
  message(FATAL_ERROR "reversing the input rows changed the result")
endif()
