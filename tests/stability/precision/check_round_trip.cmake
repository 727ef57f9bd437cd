# Float data survives --output and --input exactly: the state of md stored as
# float, written after 5 steps, read back and written again, gives the same
# file byte for byte (each float is written as the double it widens to).
# Usage: cmake -DPROGRAM=md_float -DDIR=... -P check_round_trip.cmake
include(${CMAKE_CURRENT_LIST_DIR}/../../cmake/program_run.cmake)
run(--set N=500 --steps 5 --seed 4 --output ${DIR}/written.csv)
run(--set N=500 --steps 0 --input ${DIR}/written.csv --output ${DIR}/read_back.csv)
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${DIR}/written.csv ${DIR}/read_back.csv
                RESULT_VARIABLE different)
if(different)
  message(FATAL_ERROR "float data changed through --output and --input")
endif()
