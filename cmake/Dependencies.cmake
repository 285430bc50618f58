# Every dependency comes from Debian's packages (scripts/install-deps.sh installs them).
find_package(Eigen3 3.3 REQUIRED NO_MODULE)
find_package(PkgConfig REQUIRED)
pkg_check_modules(SERIALPORT REQUIRED IMPORTED_TARGET libserialport)
pkg_check_modules(LIBLOUIS   REQUIRED IMPORTED_TARGET liblouis)
find_package(Threads REQUIRED)
if(ARMADILLO_BUILD_TESTS)
    find_package(Catch2 2 REQUIRED)   # Debian's catch2 is v2 (single header)
endif()
