# msdeform_library(<target> <export name> [INTERNAL <header>...]) makes
# <target> one of the installed libraries: alias msdeform::<export name>,
# headers included as <msdeform/<folder>/<name>.h> in the build tree and after
# installation (in the build tree only for the targets that link it), and its
# folder's headers, but the INTERNAL ones, installed under
# include/msdeform/<folder>/.
function(msdeform_library target export_name)
  cmake_parse_arguments(ARG "" "" "INTERNAL" ${ARGN})
  add_library(msdeform::${export_name} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${export_name})
  file(RELATIVE_PATH folder ${PROJECT_SOURCE_DIR} ${CMAKE_CURRENT_SOURCE_DIR})
  # The folder's own include root: include/<folder>/msdeform/<folder> -> the
  # folder. PUBLIC, so the targets that link this one see it, and only those.
  set(root ${MSDEFORM_BUILD_INCLUDE_DIR}/${folder})
  if(NOT EXISTS ${root}/msdeform/${folder})
    file(MAKE_DIRECTORY ${root}/msdeform)
    file(CREATE_LINK ${CMAKE_CURRENT_SOURCE_DIR} ${root}/msdeform/${folder} SYMBOLIC)
  endif()
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${root}>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  file(GLOB headers CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.h)
  foreach(internal IN LISTS ARG_INTERNAL)
    list(REMOVE_ITEM headers ${CMAKE_CURRENT_SOURCE_DIR}/${internal})
  endforeach()
  set_property(GLOBAL APPEND PROPERTY MSDEFORM_LIBRARIES ${target})
  set_property(TARGET ${target} PROPERTY MSDEFORM_HEADERS ${headers})
  set_property(TARGET ${target} PROPERTY MSDEFORM_FOLDER ${folder})
endfunction()

# The folders whose C++ tests are the libraries' own (label "library"; apps:
# the flags library's, tests/apps/flags): the sanitizer pass of
# scripts/run_tests.sh builds and runs only these (target
# msdeform_library_tests; docs/decisions/robustness.md). The experiments'
# tests run the table and lab programs' code at length and stay out.
set(MSDEFORM_LIBRARY_TEST_FOLDERS core energies solvers scales methods fuzz examples docs apps)

# msdeform_test(<folder>/<name>_test) adds tests/<folder>/<name>_test.cc as one
# executable and one ctest named "<folder>/<name>_test", linked with the shared
# test main and the given libraries; labelled "library" when its folder is one
# of MSDEFORM_LIBRARY_TEST_FOLDERS.
function(msdeform_test name)
  cmake_parse_arguments(ARG "" "" "LIBS" ${ARGN})
  string(REPLACE "/" "_" target "${name}")
  add_executable(${target} ${PROJECT_SOURCE_DIR}/tests/${name}.cc)
  target_link_libraries(${target} PRIVATE msdeform_test_main ${ARG_LIBS})
  add_test(NAME ${name} COMMAND ${target}
           WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
  string(REGEX MATCH "^[^/]+" folder "${name}")
  if(folder IN_LIST MSDEFORM_LIBRARY_TEST_FOLDERS)
    set_property(TEST ${name} APPEND PROPERTY LABELS library)
    set_property(GLOBAL APPEND PROPERTY MSDEFORM_LIBRARY_TEST_TARGETS ${target})
  endif()
endfunction()

# msdeform_tests(<folder> LIBS <library>... [LABELS <label>...]) adds every
# tests/<folder>/*_test.cc with msdeform_test, linked with the folder's
# libraries, and gives each the labels. A test that needs more is added by its
# own msdeform_test line before this call, and is left as it is here. A new
# file is found at the next build (CONFIGURE_DEPENDS).
function(msdeform_tests folder)
  cmake_parse_arguments(ARG "" "" "LIBS;LABELS" ${ARGN})
  file(GLOB sources CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/tests/${folder}/*_test.cc)
  foreach(source IN LISTS sources)
    get_filename_component(name ${source} NAME_WE)
    string(REPLACE "/" "_" target "${folder}/${name}")
    if(NOT TARGET ${target})
      msdeform_test(${folder}/${name} LIBS ${ARG_LIBS})
    endif()
    if(ARG_LABELS)
      set_property(TEST ${folder}/${name} APPEND PROPERTY LABELS ${ARG_LABELS})
    endif()
  endforeach()
endfunction()

# msdeform_benchmark(<name>) adds bench/<name>_benchmark.cc with Google Benchmark.
function(msdeform_benchmark name)
  cmake_parse_arguments(ARG "" "" "LIBS" ${ARGN})
  add_executable(${name}_benchmark ${PROJECT_SOURCE_DIR}/bench/${name}_benchmark.cc)
  target_link_libraries(${name}_benchmark PRIVATE ${ARG_LIBS} benchmark::benchmark)
  set_target_properties(${name}_benchmark PROPERTIES
                        RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/bench)
endfunction()
