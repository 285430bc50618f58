# Helpers that give every module, test and benchmark the same shape.

# Warnings for project code only (dependencies are included as SYSTEM headers).
add_library(armadillo_warnings INTERFACE)
target_compile_options(armadillo_warnings INTERFACE
    $<$<CXX_COMPILER_ID:GNU,Clang>:-Wall -Wextra -Wnon-virtual-dtor -Wdouble-promotion>
    $<$<CXX_COMPILER_ID:GNU>:-Wshadow=local>   # clang has no -Wshadow=local
    # GCC 12 reports false -Wrestrict positives inside libstdc++ for std::string concatenation
    # (GCC bug 105651); they point into system headers, not at project code.
    $<$<CXX_COMPILER_ID:GNU>:-Wno-restrict>)
# No -ffast-math / -Ofast anywhere in the core: they erase the NaN guards (STYLE.md convention 10).

# armadillo_module(<name> SOURCES ... [DEPENDS armadillo_x ...] [LIBS ...])
# Builds the static library armadillo_<name>; headers are included as "<Folder>/<File>.h".
function(armadillo_module name)
    cmake_parse_arguments(M "" "" "SOURCES;DEPENDS;LIBS" ${ARGN})
    add_library(armadillo_${name} STATIC ${M_SOURCES})
    target_include_directories(armadillo_${name} PUBLIC ${PROJECT_SOURCE_DIR}/Source)
    target_link_libraries(armadillo_${name} PUBLIC ${M_DEPENDS} ${M_LIBS} Eigen3::Eigen
                                            PRIVATE armadillo_warnings)
    target_compile_definitions(armadillo_${name} PUBLIC EIGEN_MPL2_ONLY)
endfunction()

# armadillo_test(<name> SOURCES ... DEPENDS ...) — one Catch2 executable tests_<name>, one ctest entry
# per TEST_CASE so CI output names what failed.
function(armadillo_test name)
    cmake_parse_arguments(T "" "" "SOURCES;DEPENDS" ${ARGN})
    add_executable(tests_${name} ${T_SOURCES})
    target_link_libraries(tests_${name} PRIVATE armadillo_catch_main ${T_DEPENDS} armadillo_warnings)
    target_compile_definitions(tests_${name} PRIVATE
        ARMADILLO_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
        ARMADILLO_SHARED_DIR="${PROJECT_SOURCE_DIR}/../shared"
        ARMADILLO_BINARY_DIR="${PROJECT_BINARY_DIR}")
    add_test(NAME ${name} COMMAND tests_${name} --order rand --warn NoAssertions)
    set_tests_properties(${name} PROPERTIES TIMEOUT 600)
endfunction()

# armadillo_benchmark(<name> SOURCES ... DEPENDS ...) — prints numbers, never pass/fail on time.
function(armadillo_benchmark name)
    cmake_parse_arguments(B "" "" "SOURCES;DEPENDS" ${ARGN})
    add_executable(bench_${name} ${B_SOURCES})
    target_link_libraries(bench_${name} PRIVATE ${B_DEPENDS} armadillo_warnings)
    target_compile_definitions(bench_${name} PRIVATE
        ARMADILLO_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
        ARMADILLO_SHARED_DIR="${PROJECT_SOURCE_DIR}/../shared"
        ARMADILLO_BINARY_DIR="${PROJECT_BINARY_DIR}")
endfunction()
