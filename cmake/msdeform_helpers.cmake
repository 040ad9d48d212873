# msdeform_test(<folder>/<name>_test) adds tests/<folder>/<name>_test.cc as one
# executable and one ctest named "<folder>/<name>_test", linked with the shared
# test main and the given libraries.
function(msdeform_test name)
  cmake_parse_arguments(ARG "" "" "LIBS" ${ARGN})
  string(REPLACE "/" "_" target "${name}")
  add_executable(${target} ${CMAKE_SOURCE_DIR}/tests/${name}.cc)
  target_link_libraries(${target} PRIVATE msdeform_test_main ${ARG_LIBS})
  add_test(NAME ${name} COMMAND ${target}
           WORKING_DIRECTORY ${CMAKE_SOURCE_DIR})
endfunction()

# msdeform_benchmark(<name>) adds bench/<name>_benchmark.cc with Google Benchmark.
function(msdeform_benchmark name)
  cmake_parse_arguments(ARG "" "" "LIBS" ${ARGN})
  add_executable(${name}_benchmark ${CMAKE_SOURCE_DIR}/bench/${name}_benchmark.cc)
  target_link_libraries(${name}_benchmark PRIVATE ${ARG_LIBS} benchmark::benchmark)
  set_target_properties(${name}_benchmark PROPERTIES
                        RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/bench)
endfunction()
