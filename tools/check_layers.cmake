# The engine's one-way chain, enforced: every non-test file of engine/NAME/ may include headers of
# NAME itself and of the layers NAME depends on, directly or through others, as declared by
# metamer_layer() in CMakeLists.txt (written to LAYERS, one "name: dep dep" line per layer). Any
# other engine header is an include that runs upward (or sideways) and fails the build, naming the
# file, the line and what the layer may include.
#
#   cmake -DLAYERS=build/layers.txt -DENGINE=engine [-DSTAMP=file] -P tools/check_layers.cmake
cmake_minimum_required(VERSION 3.25)
if(NOT LAYERS OR NOT ENGINE)
  message(FATAL_ERROR "usage: cmake -DLAYERS=FILE -DENGINE=DIR [-DSTAMP=FILE] -P check_layers.cmake")
endif()

file(STRINGS ${LAYERS} lines)
set(layers "")
foreach(line ${lines})
  if(NOT line MATCHES "^([a-z_]+):(.*)$")
    message(FATAL_ERROR "${LAYERS}: '${line}' is not 'name: deps'")
  endif()
  set(name ${CMAKE_MATCH_1})
  string(STRIP "${CMAKE_MATCH_2}" deps)
  separate_arguments(deps)
  list(APPEND layers ${name})
  set(direct_${name} ${deps})
endforeach()

# The transitive closure, depth first (the declared graph has no cycle: CMake's static libraries
# would not link otherwise, and this loop would not end).
function(closure name out)
  set(result ${name})
  foreach(dep ${direct_${name}})
    closure(${dep} sub)
    list(APPEND result ${sub})
  endforeach()
  list(REMOVE_DUPLICATES result)
  set(${out} ${result} PARENT_SCOPE)
endfunction()

set(failures 0)
foreach(name ${layers})
  if(NOT IS_DIRECTORY ${ENGINE}/${name})
    continue()  # app has its own folder; every declared layer does
  endif()
  closure(${name} allowed)
  file(GLOB files ${ENGINE}/${name}/*.h ${ENGINE}/${name}/*.cpp)
  list(FILTER files EXCLUDE REGEX "_test\\.cpp$")
  foreach(f ${files})
    file(STRINGS ${f} includes REGEX "^#include \"[a-z_]+/")
    foreach(inc ${includes})
      string(REGEX MATCH "^#include \"([a-z_]+)/" _ "${inc}")
      set(target ${CMAKE_MATCH_1})
      list(FIND layers ${target} known)
      list(FIND allowed ${target} ok)
      if(known GREATER -1 AND ok EQUAL -1)
        file(RELATIVE_PATH rel ${ENGINE}/.. ${f})
        string(REPLACE ";" ", " may "${allowed}")
        message(SEND_ERROR "${rel}: ${inc}: the ${name} layer may include only ${may} (docs/architecture.md, \"Layers\")")
        math(EXPR failures "${failures} + 1")
      endif()
    endforeach()
  endforeach()
endforeach()
if(failures GREATER 0)
  message(FATAL_ERROR "${failures} include(s) run against the engine's layering")
endif()
if(STAMP)
  file(TOUCH ${STAMP})
endif()
