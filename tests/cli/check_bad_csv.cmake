# Bad CSV files given to a generated program's --input (issue 9): for each
# one the driver exits 1 and prints exactly
#
#   FILE:LINE:COL: error: MESSAGE
#   the line, as shown
#   a caret under the column
#
# (a file it cannot open: "FILE: error: MESSAGE"), with no signal, no hang
# and no sanitizer report; and it writes nothing: the --output file that was
# there before the run is byte-identical, there is no FILE.tmp and no VTK
# frame. Then files it should read (a header without rows, CRLF, spaces, a
# leading '+', ...) are read, and --output writes back what they hold.
#
# Usage: cmake -DPROGRAM=csv_input -DMD=md -DSPH=sph_dam_break -DDATA=tests/cli/csv
#              -DDIR=scratch -DPART=rejected|accepted|special|two_sets -P check_bad_csv.cmake
# PROGRAM is tests/cli/csv_input.part's program (columns id, p_0 .. p_2, v_0
# .. v_2, hits, moving; periodic along x, reflecting along y, unbounded
# along z); MD is the md example (a cell list), for 0 particles; SPH the
# sph_dam_break example, for two sets. DATA holds
# the files CMake cannot write (NUL bytes: csv/README.md). Every failure is
# listed at the end, not only the first.
set(DIR ${DIR}/${PART})
file(REMOVE_RECURSE ${DIR})
file(MAKE_DIRECTORY ${DIR}/frames)
set(H "id,p_0,p_1,p_2")  # the header most cases share
set(previous "id,p_0,p_1,p_2\n7,0.5,0.5,0.5\n")  # --output's file before each run

function(fail name text)  # one string: messages hold semicolons
  set_property(GLOBAL APPEND_STRING PROPERTY failures "\n\n${name}: ${text}")
  get_property(count GLOBAL PROPERTY failure_count)
  math(EXPR count "${count} + 1")
  set_property(GLOBAL PROPERTY failure_count ${count})
endfunction()
set_property(GLOBAL PROPERTY failure_count 0)

# Control characters other than tab and newline, for "the message is printable".
set(control "")
foreach(code RANGE 1 31)
  if(NOT code EQUAL 9 AND NOT code EQUAL 10)
    string(ASCII ${code} c)
    string(APPEND control "${c}")
  endif()
endforeach()
string(ASCII 127 c)
string(APPEND control "${c}")

# Runs PROGRAM ARGS... with --output and --vtk into DIR, after writing
# `previous` to the output; sets `status`, `out` and `err` in the caller and
# records a failure for a signal, a timeout, a sanitizer report or any output
# left behind.
macro(run_failing name)
  file(WRITE ${DIR}/out.csv "${previous}")
  file(REMOVE ${DIR}/out.csv.tmp)
  file(GLOB frames ${DIR}/frames/*)
  if(frames)
    file(REMOVE ${frames})
  endif()
  execute_process(COMMAND ${ARGN} --quiet --steps 2 --output ${DIR}/out.csv
                          --vtk ${DIR}/frames/run --every 1
                  RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 30)
  if(NOT status STREQUAL "1")
    fail(${name} "expected exit status 1, got '${status}'; it printed:\n${out}${err}")
  endif()
  if("${out}${err}" MATCHES "Sanitizer|runtime error:")
    fail(${name} "a sanitizer report:\n${err}")
  endif()
  if("${out}${err}" MATCHES "[${control}]")
    fail(${name} "the message holds a control character")
  endif()
  file(READ ${DIR}/out.csv now)
  if(NOT now STREQUAL previous)
    fail(${name} "the previous --output file changed to:\n${now}")
  endif()
  if(EXISTS ${DIR}/out.csv.tmp)
    fail(${name} "out.csv.tmp was left behind")
  endif()
  file(GLOB frames ${DIR}/frames/*)
  if(frames)
    fail(${name} "VTK files were written: ${frames}")
  endif()
endmacro()

# check(NAME INPUT WHERE MESSAGE SHOWN [CARET]): PROGRAM --input INPUT must
# print "INPUT:WHERE: error: MESSAGE", the line SHOWN, and a caret under
# column CARET of SHOWN (1-based, in characters; by default WHERE's
# column, the tabs before it copied). SHOWN "*"
# accepts any one-line quote with a caret under it (binary garbage).
function(check name input where message shown)
  run_failing(${name} ${PROGRAM} --input ${input})
  string(REGEX REPLACE "^[0-9]+:" "" column "${where}")
  set(expected "${input}:${where}: error: ${message}\n")
  if(shown STREQUAL "*")
    string(LENGTH "${expected}" length)
    string(SUBSTRING "${err}" 0 ${length} start)
    string(SUBSTRING "${err}" ${length} -1 rest)
    if(NOT start STREQUAL expected OR NOT rest MATCHES "^[^\n]*\n[ \t]*\\^\n$")
      fail(${name} "expected '${expected}', a line and a caret; got:\n${err}")
    endif()
    return()
  endif()
  if(ARGC GREATER 5)  # where the column is not the caret's (a line cut, UTF-8)
    math(EXPR before "${ARGV5} - 1")
    string(REPEAT " " ${before} caret)
  else()
    math(EXPR before "${column} - 1")
    string(SUBSTRING "${shown}" 0 ${before} caret)
    string(REGEX REPLACE "[^\t]" " " caret "${caret}")
  endif()
  string(APPEND expected "${shown}\n${caret}^\n")
  if(NOT err STREQUAL expected)
    fail(${name} "expected:\n${expected}got:\n${err}")
  endif()
endfunction()

# bad(NAME WHERE MESSAGE SHOWN CONTENT [CARET]): CONTENT as a file, checked.
function(bad name where message shown content)
  file(WRITE ${DIR}/${name}.csv "${content}")
  check(${name} ${DIR}/${name}.csv "${where}" "${message}" "${shown}" ${ARGN})
endfunction()

# good(NAME CONTENT WRITTEN): CONTENT is read without a word, and --output
# writes WRITTEN (the set in id order, every column, shortest numbers).
set(columns "id,p_0,p_1,p_2,v_0,v_1,v_2,hits,moving")
function(good name content written)
  file(WRITE ${DIR}/${name}.csv "${content}")
  execute_process(COMMAND ${PROGRAM} --quiet --steps 0 --input ${DIR}/${name}.csv
                          --output ${DIR}/${name}.out.csv
                  RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 30)
  if(NOT status STREQUAL "0" OR NOT "${out}${err}" STREQUAL "")
    fail(${name} "expected to be read, got exit status '${status}' and:\n${out}${err}")
    return()
  endif()
  file(READ ${DIR}/${name}.out.csv now)
  if(NOT now STREQUAL "${columns}\n${written}")
    fail(${name} "--output wrote:\n${now}instead of:\n${columns}\n${written}")
  endif()
endfunction()

set(no_header "expected a header line naming the columns, such as 'id,p_0,p_1'")
set(truncated "the file ends inside this line, without its line break: is it truncated? (a complete file ends with a line break)")
set(fields "fields as in the header, got")
set(ids "column 'id' holds non-negative integer ids below 2^53, got")
set(known "the columns are id, p_0, p_1, p_2, v_0, v_1, v_2, hits, moving")
string(ASCII 27 escape)
string(ASCII 255 254 invalid_utf8)
string(ASCII 239 187 191 bom)

if(PART STREQUAL "rejected")
  # Empty, truncated, or the wrong shape.
  bad(empty 1:1 "${no_header}" "" "")
  bad(blank_lines_only 1:1 "${no_header}" "" "\n \n")
  bad(header_without_line_break 1:15 "${truncated}" "${H}" "${H}")
  bad(truncated_in_number 3:15 "${truncated}" "1,0.25,0.5,0.1" "${H}\n0,0.5,0.5,0.5\n1,0.25,0.5,0.1")
  bad(truncated_in_exponent 3:14 "${truncated}" "1,0.25,0.5,1e" "${H}\n0,0.5,0.5,0.5\n1,0.25,0.5,1e")
  bad(truncated_in_line 3:8 "${truncated}" "1,0.25," "${H}\n0,0.5,0.5,0.5\n1,0.25,")
  bad(truncated_crlf 2:7 "${truncated}" "1,0.25" "${H}\r\n1,0.25\r")
  bad(too_few_fields 2:10 "expected 4 ${fields} 3" "0,0.5,0.5" "${H}\n0,0.5,0.5\n")
  bad(too_many_fields 2:15 "expected 4 ${fields} 5" "0,0.5,0.5,0.5,1" "${H}\n0,0.5,0.5,0.5,1\n")
  bad(trailing_comma 2:15 "expected 4 ${fields} 5" "0,0.5,0.5,0.5," "${H}\n0,0.5,0.5,0.5,\n")
  bad(blank_line_inside 3:1 "blank line inside the data (only trailing blank lines are allowed)" ""
      "${H}\n0,0.5,0.5,0.5\n\n1,0.5,0.5,0.5\n")
  bad(header_of_numbers 1:1
      "the first line must name the columns, but it holds numbers; is the header line missing?"
      "0,0.5,0.5,0.5" "0,0.5,0.5,0.5\n1,0.5,0.5,0.5\n")
  bad(empty_column_name 1:12 "empty column name" "id,p_0,p_1,,p_2" "id,p_0,p_1,,p_2\n")
  bad(duplicate_column 1:12 "duplicate column name 'p_0' (also column 2)" "id,p_0,p_1,p_0,p_2"
      "id,p_0,p_1,p_0,p_2\n")

  # Numbers.
  bad(empty_field 2:7 "expected a number, got an empty field in column 'p_1'" "0,0.5,,0.5"
      "${H}\n0,0.5,,0.5\n")
  bad(not_a_number 2:7 "expected a number, got 'abc' in column 'p_1'" "0,0.5,abc,0.5"
      "${H}\n0,0.5,abc,0.5\n")
  bad(trailing_junk 2:3 "expected a number, got '0.5x' in column 'p_0'" "0,0.5x,0.5,0.5"
      "${H}\n0,0.5x,0.5,0.5\n")
  bad(two_numbers 2:3 "expected a number, got '0.5 0.25' in column 'p_0'" "0,0.5 0.25,0.5,0.5"
      "${H}\n0,0.5 0.25,0.5,0.5\n")
  bad(semicolons 2:14 "expected 4 ${fields} 1" "0;0.5;0.5;0.5" "${H}\n0;0.5;0.5;0.5\n")
  foreach(word nan NaN -nan inf -inf +inf Infinity -INFINITY)
    bad(number_${word} 2:3 "expected a finite number, got '${word}' in column 'p_0'" "0,${word},0.5,0.5"
        "${H}\n0,${word},0.5,0.5\n")
  endforeach()
  bad(overflow 2:3 "'1e400' is out of the range of a double in column 'p_0'" "0,1e400,0.5,0.5"
      "${H}\n0,1e400,0.5,0.5\n")
  bad(overflow_negative 2:3 "'-2e308' is out of the range of a double in column 'p_0'" "0,-2e308,0.5,0.5"
      "${H}\n0,-2e308,0.5,0.5\n")
  bad(underflow 2:3 "'1e-400' is too small for a double: it would read as 0 (write 0 if that is meant) in column 'p_0'"
      "0,1e-400,0.5,0.5" "${H}\n0,1e-400,0.5,0.5\n")
  bad(underflow_below_subnormals 2:3 "'2e-324' is too small for a double: it would read as 0 (write 0 if that is meant) in column 'p_0'"
      "0,2e-324,0.5,0.5" "${H}\n0,2e-324,0.5,0.5\n")
  foreach(hex 0x1p-2 0x10 1p-2 0X1.8P1)
    bad(hex_${hex} 2:3 "expected a number, got '${hex}' in column 'p_0'" "0,${hex},0.5,0.5"
        "${H}\n0,${hex},0.5,0.5\n")
  endforeach()
  bad(plus_minus 2:3 "expected a number, got '+-0.5' in column 'p_0'" "0,+-0.5,0.5,0.5"
      "${H}\n0,+-0.5,0.5,0.5\n")
  bad(plus_plus 2:3 "expected a number, got '++0.5' in column 'p_0'" "0,++0.5,0.5,0.5"
      "${H}\n0,++0.5,0.5,0.5\n")
  bad(space_after_sign 2:3 "expected a number, got '- 0.5' in column 'p_0'" "0,- 0.5,0.5,0.5"
      "${H}\n0,- 0.5,0.5,0.5\n")
  # Quoted fields are not CSV that partc reads (no field of its needs them).
  bad(quoted_header 1:1 "unknown column '\"id\"'; ${known}" "\"id\",\"p_0\",\"p_1\",\"p_2\""
      "\"id\",\"p_0\",\"p_1\",\"p_2\"\n0,0.5,0.5,0.5\n")
  bad(quoted_number 2:3 "expected a number, got '\"0.5\"' in column 'p_0'" "0,\"0.5\",0.5,0.5"
      "${H}\n0,\"0.5\",0.5,0.5\n")

  # Bytes that have no place in text: shown as '?', never sent to the terminal.
  check(nul_in_number ${DATA}/nul_in_number.csv 2:6 "a NUL byte in the text; is this a CSV file?"
        "0,0.5?,0.5,0.5")
  check(nul_in_header ${DATA}/nul_in_header.csv 1:6 "a NUL byte in the text; is this a CSV file?"
        "id,p_??,p_1,p_2")
  bad(carriage_returns_only 1:15 "a carriage return inside a line (lines end with \"\\n\" or \"\\r\\n\")"
      "${H}?0,0.5,0.5,0.5" "${H}\r0,0.5,0.5,0.5\r")
  bad(escape_sequence 2:7 "control character 0x1B in the text; is this a CSV file?" "0,0.5,?[31m,0.5"
      "${H}\n0,0.5,${escape}[31m,0.5\n")
  bad(invalid_utf8 2:3 "expected a number, got '??' in column 'p_0'" "0,??,0.5,0.5"
      "${H}\n0,${invalid_utf8},0.5,0.5\n")
  # Valid UTF-8 is shown as it is, the caret under its column in characters.
  bad(utf8_names 1:19 "duplicate column name 'é' (also column 5)" "${H},é,é" "${H},é,é\n" 18)
  # 4 KB of pseudo-random bytes (1 to 255; an LCG, the same every run), as
  # the whole file and as the rows after a good header.
  set(seed 9)
  set(garbage "")
  foreach(k RANGE 1 4096)
    math(EXPR seed "(${seed} * 1103515245 + 12345) % 2147483648")
    math(EXPR code "(${seed} >> 16) % 255 + 1")
    string(ASCII ${code} c)
    string(APPEND garbage "${c}")
  endforeach()
  file(WRITE ${DIR}/garbage.csv "${garbage}")
  check(garbage ${DIR}/garbage.csv 1:6 "control character 0x14 in the text; is this a CSV file?" "*")
  file(WRITE ${DIR}/garbage_rows.csv "${H}\n${garbage}\n")
  check(garbage_rows ${DIR}/garbage_rows.csv 2:6 "control character 0x14 in the text; is this a CSV file?" "*")

  # Long lines: 10 MB of spaces before a bad field (the message shows the 100
  # bytes around it), a number of 10 MB digits, and 100000 fields.
  string(REPEAT " " 10000000 spaces)
  string(REPEAT " " 60 sixty)
  bad(ten_megabyte_line 2:10000011 "expected a number, got 'x' in column 'p_2'" "...${sixty}x"
      "${H}\n0,0.5,0.5,${spaces}x\n" 64)
  string(REPEAT "1" 10000000 ones)
  string(SUBSTRING "${ones}" 0 40 forty)
  string(SUBSTRING "${ones}" 0 90 ninety)
  bad(ten_megabyte_number 2:11
      "'${forty}...' (10000000 bytes) is out of the range of a double in column 'p_2'"
      "0,0.5,0.5,${ninety}..." "${H}\n0,0.5,0.5,${ones}\n")
  string(REPEAT ",0" 99996 zeros)
  string(SUBSTRING "${zeros}" 0 87 shown_zeros)
  bad(hundred_thousand_fields 2:15 "expected 4 ${fields} 100000" "0,0.5,0.5,0.5${shown_zeros}..."
      "${H}\n0,0.5,0.5,0.5${zeros}\n")
  string(REPEAT ",c" 99996 names)
  string(SUBSTRING "${names}" 0 86 shown_names)
  bad(hundred_thousand_columns 1:18 "duplicate column name 'c' (also column 5)" "${H}${shown_names}..."
      "${H}${names}\n0,0.5,0.5,0.5${zeros}\n")

  # Ids and other integers.
  bad(duplicate_id 4:1 "duplicate id 3 (also on line 2)" "3,0.2,0.2,0.2"
      "${H}\n3,0.5,0.5,0.5\n4,0.1,0.1,0.1\n3,0.2,0.2,0.2\n")
  bad(negative_id 2:1 "${ids} -1" "-1,0.5,0.5,0.5" "${H}\n-1,0.5,0.5,0.5\n")
  bad(fractional_id 2:1 "${ids} 1.5" "1.5,0.5,0.5,0.5" "${H}\n1.5,0.5,0.5,0.5\n")
  bad(id_2_to_53 2:1 "${ids} 9007199254740992" "9007199254740992,0,0,0" "${H}\n9007199254740992,0,0,0\n")
  bad(id_over_2_to_53 2:1 "${ids} 9007199254740992 (the double nearest to '9007199254740993')"
      "9007199254740993,0,0,0" "${H}\n9007199254740993,0,0,0\n")
  bad(id_over_2_to_63 2:1 "${ids} 9223372036854775808 (the double nearest to '9223372036854775809')"
      "9223372036854775809,0,0,0" "${H}\n9223372036854775809,0,0,0\n")
  bad(id_over_2_to_64 2:1 "${ids} 18446744073709551616 (the double nearest to '18446744073709551617')"
      "18446744073709551617,0,0,0" "${H}\n18446744073709551617,0,0,0\n")
  bad(id_1e300 2:1 "${ids} 1e+300 (the double nearest to '1e300')" "1e300,0,0,0" "${H}\n1e300,0,0,0\n")
  bad(int_fraction 2:9 "column 'hits' holds integers, got 0.5" "0,0,0,0,0.5" "${H},hits\n0,0,0,0,0.5\n")
  bad(int_huge 2:9 "column 'hits' holds integers, got 1e+19 (the double nearest to '1e19')" "0,0,0,0,1e19"
      "${H},hits\n0,0,0,0,1e19\n")
  bad(bool_two 2:9 "column 'moving' holds 0 or 1 (a bool), got 2" "0,0,0,0,2" "${H},moving\n0,0,0,0,2\n")

  # Columns.
  bad(missing_position 1:11 "missing column 'p_2' (positions are required)" "id,p_0,p_1"
      "id,p_0,p_1\n0,0.5,0.5\n")
  bad(no_position 1:3 "missing column 'p_0' (positions are required)" "id" "id\n0\n")
  bad(missing_vec_component 1:23 "missing column 'v_1' (a vec needs all its components)" "${H},v_0,v_2"
      "${H},v_0,v_2\n0,0,0,0,1,1\n")
  bad(unknown_column 1:16 "unknown column 'x'; ${known}" "${H},x" "${H},x\n0,0,0,0,1\n")

  # y reflects at 0 and 1: a particle outside would be folded in unseen.
  bad(outside_reflecting_face 3:7 "p_1 = 1.5 is outside the reflecting faces at 0 and 1" "1,0.5,1.5,0"
      "${H}\n0,0.5,0.5,0\n1,0.5,1.5,0\n")
  bad(below_reflecting_face 2:7 "p_1 = -1e-300 is outside the reflecting faces at 0 and 1"
      "0,0.5,-1e-300,0" "${H}\n0,0.5,-1e-300,0\n")
endif()

if(PART STREQUAL "accepted")
  good(header_only "${H}\n" "")
  good(header_only_crlf "${H}\r\n" "")
  good(crlf "${H}\r\n1,0.5,0.25,0.125\r\n0,0.75,0.5,2\r\n"
       "0,0.75,0.5,2,0,0,0,0,0\n1,0.5,0.25,0.125,0,0,0,0,0\n")
  good(spaces_tabs_plus " id ,\tp_0, p_1 ,p_2\t\n +1 , +0.5,\t0.25\t, -0.0 \n"
       "1,0.5,0.25,-0,0,0,0,0,0\n")
  good(byte_order_mark "${bom}${H}\n0,0.5,0.5,0.5\n" "0,0.5,0.5,0.5,0,0,0,0,0\n")
  good(trailing_blank_lines "${H}\n0,0.5,0.5,0.5\n\n  \n\t" "0,0.5,0.5,0.5,0,0,0,0,0\n")
  good(no_id_column "p_0,p_1,p_2\n0.5,0.5,0.5\n0.25,0.25,0.25\n"
       "0,0.5,0.5,0.5,0,0,0,0,0\n1,0.25,0.25,0.25,0,0,0,0,0\n")
  good(number_forms "${H}\n0,.5,.25,5.\n1,1E-3,00.5,-0.25e1\n2,0.5,0.5,1e+2\n"
       "0,0.5,0.25,5,0,0,0,0,0\n1,0.001,0.5,-2.5,0,0,0,0,0\n2,0.5,0.5,100,0,0,0,0,0\n")
  # Subnormals are read as they are (1e-400 is refused: it would read as 0).
  good(subnormals "${H}\n0,5e-324,1e-310,0.5\n" "0,5e-324,1e-310,0.5,0,0,0,0,0\n")
  # x is periodic (wrapped), z unbounded (anything finite goes).
  good(on_reflecting_faces "${H}\n0,0.5,0,0\n1,0.5,1,0\n"
       "0,0.5,0,0,0,0,0,0,0\n1,0.5,1,0,0,0,0,0,0\n")
  good(wrapped_and_unbounded "${H}\n0,1.25,0.5,1e300\n1,-0.25,0.5,-1e300\n"
       "0,0.25,0.5,1e+300,0,0,0,0,0\n1,0.75,0.5,-1e+300,0,0,0,0,0\n")
  good(largest_id "${H},hits,moving\n9007199254740991,0,0,0,-9007199254740992,1\n"
       "9007199254740991,0,0,0,0,0,0,-9007199254740992,1\n")
  good(every_column "${H},v_0,v_1,v_2,hits,moving\n2,0.5,0.5,0.5,1,2,3,4,1\n"
       "2,0.5,0.5,0.5,1,2,3,4,1\n")
  string(REPEAT "0" 10000000 zeros)
  good(ten_megabyte_number "${H}\n0,0.5,0.5,0.5${zeros}\n" "0,0.5,0.5,0.5,0,0,0,0,0\n")
  # No particles: the steps and the searches run on none (md: a cell list).
  file(WRITE ${DIR}/md_empty.csv "id,p_0,p_1\n")
  execute_process(COMMAND ${MD} --quiet --steps 3 --input ${DIR}/md_empty.csv
                          --output ${DIR}/md_empty.out.csv
                  RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 30)
  file(READ ${DIR}/md_empty.out.csv written)
  if(NOT status STREQUAL "0" OR NOT written STREQUAL "id,p_0,p_1,v_0,v_1\n")
    fail(md_header_only "exit status '${status}', wrote '${written}':\n${out}${err}")
  endif()
endif()

if(PART STREQUAL "special")
  # Paths that are no CSV file: no line to point at.
  run_failing(nonexistent ${PROGRAM} --input ${DIR}/nowhere.csv)
  if(NOT err STREQUAL "${DIR}/nowhere.csv: error: cannot open: No such file or directory\n")
    fail(nonexistent "got:\n${err}")
  endif()
  run_failing(directory ${PROGRAM} --input ${DIR}/frames)
  if(NOT err STREQUAL "${DIR}/frames: error: this is a directory, not a CSV file\n")
    fail(directory "got:\n${err}")
  endif()
  # /dev/zero: one endless line of NUL bytes, cut at 16 MiB.
  string(REPEAT "?" 100 hundred)
  check(dev_zero /dev/zero 1:1 "a line longer than 16 MiB; is this a CSV file?" "${hundred}...")
  # Through a named pipe, which cannot be read twice: the line is still quoted.
  file(WRITE ${DIR}/piped.csv "${H}\n0,0.5,0.5,0.5\n1,0.5,oops,0.5\n")
  execute_process(COMMAND mkfifo ${DIR}/fifo.csv RESULT_VARIABLE made)
  if(made EQUAL 0)
    run_failing(fifo sh -c "cat '${DIR}/piped.csv' > '${DIR}/fifo.csv' & exec \"$0\" \"$@\""
                ${PROGRAM} --input ${DIR}/fifo.csv)
    if(NOT err STREQUAL "${DIR}/fifo.csv:3:7: error: expected a number, got 'oops' in column 'p_1'\n1,0.5,oops,0.5\n      ^\n")
      fail(fifo "got:\n${err}")
    endif()
  endif()
  # The input is the output: a bad file is left as it is.
  file(WRITE ${DIR}/same.csv "${H}\n0,0.5,0.5\n")
  execute_process(COMMAND ${PROGRAM} --quiet --steps 1 --input ${DIR}/same.csv --output ${DIR}/same.csv
                  RESULT_VARIABLE status ERROR_VARIABLE err TIMEOUT 30)
  file(READ ${DIR}/same.csv now)
  if(NOT status STREQUAL "1" OR NOT now STREQUAL "${H}\n0,0.5,0.5\n" OR EXISTS ${DIR}/same.csv.tmp)
    fail(input_is_output "exit status '${status}', the file now:\n${now}${err}")
  endif()
endif()

if(PART STREQUAL "two_sets")
  # Two sets (SPH's fluid F and walls W), the second's file truncated: the
  # first set's output is not written either.
  execute_process(COMMAND ${SPH} --quiet --steps 0 --output ${DIR}/state.csv RESULT_VARIABLE status)
  file(READ ${DIR}/state_W.csv walls)
  string(LENGTH "${walls}" length)
  math(EXPR length "${length} - 3")
  string(SUBSTRING "${walls}" 0 ${length} walls)
  file(WRITE ${DIR}/truncated_W.csv "${walls}")
  file(STRINGS ${DIR}/truncated_W.csv lines)
  list(LENGTH lines count)
  list(GET lines -1 last)
  string(LENGTH "${last}" column)
  math(EXPR column "${column} + 1")
  foreach(set F W)
    file(WRITE ${DIR}/out_${set}.csv "${previous}")
  endforeach()
  execute_process(COMMAND ${SPH} --quiet --steps 1 --input F=${DIR}/state_F.csv
                          --input W=${DIR}/truncated_W.csv --output ${DIR}/out.csv
                  RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 30)
  string(REPEAT " " ${column} caret)
  string(REGEX REPLACE " $" "^" caret "${caret}")
  if(NOT status STREQUAL "1" OR NOT err STREQUAL
     "${DIR}/truncated_W.csv:${count}:${column}: error: ${truncated}\n${last}\n${caret}\n")
    fail(two_sets "exit status '${status}':\n${out}${err}")
  endif()
  foreach(set F W)
    file(READ ${DIR}/out_${set}.csv now)
    if(NOT now STREQUAL previous OR EXISTS ${DIR}/out_${set}.csv.tmp)
      fail(two_sets "out_${set}.csv was touched")
    endif()
  endforeach()
endif()

get_property(count GLOBAL PROPERTY failure_count)
if(count GREATER 0)
  get_property(failures GLOBAL PROPERTY failures)
  message(FATAL_ERROR "${count} bad-CSV case(s) failed:${failures}")
endif()
