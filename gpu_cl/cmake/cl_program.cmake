# Concatenates OpenCL C sources into one program string:
#   cmake -DOUT=program.cl -DINPUTS="a.h;b.h;k.cl" -P cl_program.cmake
# A line `#include "x.h"` whose x.h is one of the inputs (by file name) becomes a // comment:
# that file is already in the program above it, and clBuildProgram gets no include path. Any
# other quoted include is an error, so the program never depends on the source tree at run time.
set(names "")
foreach(in ${INPUTS})
  get_filename_component(n "${in}" NAME)
  list(APPEND names "${n}")
endforeach()
set(text "")
foreach(in ${INPUTS})
  get_filename_component(n "${in}" NAME)
  file(READ "${in}" body)
  # Directives only: an #include at the start of a line (after optional blanks).
  set(body "\n${body}")
  string(REGEX MATCHALL "\n[ \t]*#[ \t]*include[ \t]*\"[^\"\n]+\"" incs "${body}")
  foreach(inc IN LISTS incs)
    string(REGEX REPLACE ".*\"([^\"]+)\"" "\\1" file "${inc}")
    get_filename_component(file_name "${file}" NAME)
    list(FIND names "${file_name}" found)
    if(found EQUAL -1)
      message(FATAL_ERROR "${in}: #include \"${file}\" is not one of the program's inputs")
    endif()
    string(REPLACE "${inc}" "\n// #include \"${file}\": inlined above" body "${body}")
  endforeach()
  string(APPEND text "// ---- ${n} ----${body}\n")
endforeach()
file(WRITE "${OUT}.tmp" "${text}")
file(RENAME "${OUT}.tmp" "${OUT}")
