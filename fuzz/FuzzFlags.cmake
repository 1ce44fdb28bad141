# Compiler flags of a fuzzing build (CONFTRACK_BUILD_FUZZERS=ON), included
# by the top-level CMakeLists.txt before the library modules so that every
# library source is instrumented for libFuzzer's coverage feedback and
# checked by AddressSanitizer and UndefinedBehaviorSanitizer. UB aborts at
# the first report (-fno-sanitize-recover) so that libFuzzer records it as
# a crash. The fuzzer executables add -fsanitize=fuzzer at link time
# (fuzz/CMakeLists.txt).
if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
  message(FATAL_ERROR
    "CONFTRACK_BUILD_FUZZERS needs clang (libFuzzer), e.g. "
    "CC=clang-14 CXX=clang++-14 cmake -S . -B build-fuzz "
    "-DCONFTRACK_BUILD_FUZZERS=ON; the compiler is ${CMAKE_CXX_COMPILER_ID}")
endif()
set(CONFTRACK_SANITIZE_FLAGS
    -fsanitize=fuzzer-no-link,address,undefined
    -fno-sanitize-recover=undefined -fno-omit-frame-pointer -g)
add_compile_options(${CONFTRACK_SANITIZE_FLAGS})
add_link_options(-fsanitize=address,undefined)
