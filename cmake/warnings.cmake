# Warnings as errors for the project's own code: an INTERFACE target that each
# of our targets links PRIVATE, so consumers and third-party headers are not
# affected.
add_library(rockcal_warnings INTERFACE)
target_compile_options(rockcal_warnings INTERFACE
  -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor -Wold-style-cast
  -Wcast-align -Woverloaded-virtual -Wnull-dereference -Werror)

# Address + undefined-behaviour sanitizers (CI runs the tests with them).
add_library(rockcal_sanitizers INTERFACE)
if(ROCKCAL_SANITIZE)
  # GCC 12 reports false "maybe-uninitialized" warnings in std::optional and
  # std::vector moves once the address sanitizer instruments them at -O2.
  #
  # Only the code under test is instrumented: the libraries and rockcal, not the
  # test executables' own code (targets with the property ROCKCAL_TEST_CODE),
  # which still link the sanitizers' run-time, so every library call a test
  # makes is checked. Instrumenting GoogleTest's macros too cost 2.5x their
  # compile time (17 s against 6.5 s a test file), a third of CI's build.
  set(test_code "$<BOOL:$<TARGET_PROPERTY:ROCKCAL_TEST_CODE>>")
  target_compile_options(rockcal_sanitizers INTERFACE
    $<$<NOT:${test_code}>:-fsanitize=address,undefined>
    $<$<NOT:${test_code}>:-fno-sanitize-recover=all>
    -fno-omit-frame-pointer -Wno-maybe-uninitialized)
  target_link_options(rockcal_sanitizers INTERFACE -fsanitize=address,undefined)
  # Eigen allocates a dynamic matrix with the system's malloc, except under
  # the address sanitizer (__SANITIZE_ADDRESS__), where it over-allocates and
  # aligns by hand. Instrumented and test code would then disagree on how a
  # matrix is freed, and the linker keeps one copy of each inline allocator
  # for both: a matrix made on one side and freed on the other corrupts the
  # heap. Every file of the sanitized build takes Eigen's own allocator.
  target_compile_definitions(rockcal_sanitizers INTERFACE EIGEN_MALLOC_ALREADY_ALIGNED=0)
endif()

# rockcal_add_library(NAME folder SOURCES ... DEPS ...)
function(rockcal_add_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS" ${ARGN})
  add_library(rockcal_${name} ${ARG_SOURCES})
  add_library(rockcal::${name} ALIAS rockcal_${name})
  target_include_directories(rockcal_${name} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include)
  target_link_libraries(rockcal_${name} PUBLIC ${ARG_PUBLIC_DEPS} rockcal_sanitizers
                                        PRIVATE rockcal_warnings)
  # parallel/ stays one file each: compiled as one at -O2, GCC 12 warns of
  # an uninitialised string in it (a false positive, an error under -Werror).
  if(ROCKCAL_UNITY_BUILD AND NOT name STREQUAL "parallel")
    set_target_properties(rockcal_${name} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 8)
  endif()
endfunction()
