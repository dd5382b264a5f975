# One CTest test per GoogleTest suite of an executable (TARGET.Suite running
# --gtest_filter=Suite.*), listed from the built executable when ctest starts.
#
# gtest_discover_tests registers one CTest test per test case, and every test
# is then a process of its own: with the sanitizers, and GDAL's libraries
# loaded by every process, starting one costs about half a second, which was
# a fifth of the sanitized suite's time. A failing suite prints the whole
# GoogleTest output (ctest --output-on-failure), failed cases named.
#
# rockcal_add_suite_tests(TARGET LABEL TIMEOUT)
function(rockcal_add_suite_tests target label timeout)
  set(script "${CMAKE_CURRENT_BINARY_DIR}/${target}_suites.cmake")
  file(GENERATE OUTPUT "${script}" CONTENT "\
set(exe \"$<TARGET_FILE:${target}>\")
if(NOT EXISTS \"\${exe}\")
  add_test(${target}.NOT_BUILT \"\${exe}\")
  return()
endif()
execute_process(COMMAND \"\${exe}\" --gtest_list_tests OUTPUT_VARIABLE listing
                RESULT_VARIABLE status ERROR_VARIABLE errors)
if(NOT status EQUAL 0)
  add_test(${target}.LISTING_FAILED \"\${exe}\" --gtest_list_tests)
  return()
endif()
string(REPLACE \"\\n\" \";\" lines \"\${listing}\")
foreach(line IN LISTS lines)
  if(line MATCHES \"^([^ #][^ ]*)\\\\.\")
    set(suite \"\${CMAKE_MATCH_1}\")
    add_test(${target}.\${suite} \"\${exe}\" \"--gtest_filter=\${suite}.*\")
    set_tests_properties(${target}.\${suite} PROPERTIES LABELS ${label} TIMEOUT ${timeout}
                         WORKING_DIRECTORY \"${CMAKE_CURRENT_BINARY_DIR}\")
  endif()
endforeach()
")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES "${script}")
endfunction()
