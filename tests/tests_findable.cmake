# Every engine header says where its tests are: a *_test.cpp beside it, or a "Tests:" line in its
# leading comment (issue 14: tests findable from the code).
#   cmake -DENGINE=engine -P tests/tests_findable.cmake
file(GLOB headers ${ENGINE}/*/*.h)
set(missing "")
foreach(h ${headers})
  if(h MATCHES "_test_util\\.h$")
    continue()  # a test helper itself
  endif()
  string(REGEX REPLACE "\\.h$" "_test.cpp" beside "${h}")
  if(EXISTS "${beside}")
    continue()
  endif()
  file(STRINGS "${h}" pointer REGEX "^// .*Tests?:")
  if(NOT pointer)
    file(RELATIVE_PATH rel "${ENGINE}/.." "${h}")
    list(APPEND missing "${rel}")
  endif()
endforeach()
if(missing)
  string(REPLACE ";" "\n  " text "${missing}")
  message(FATAL_ERROR "headers with neither a *_test.cpp beside them nor a 'Tests:' line:\n  ${text}")
endif()
