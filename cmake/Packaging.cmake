# CPack: `cpack -G DEB` in the build folder writes armadillo_<version>_amd64.deb from the install
# rules. Depends is computed by dpkg-shlibdeps from the shared libraries the binaries link.
set(CPACK_PACKAGE_NAME armadillo)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_VENDOR "ARMadillo developers")
set(CPACK_PACKAGE_CONTACT "ARMadillo developers <armadillo@armadillo.invalid>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "forearm controller and tactile display: instruments you feel")
set(CPACK_PACKAGE_DESCRIPTION
    "ARMadillo turns a forearm-worn motion sensor and a 3x3 grid of vibration motors
into an instrument you can feel, a braille display read by rolling the arm, and
a source of orientation for a DAW (after D. Sachs, MIT 2005).
This package holds the armadillo command line program (offline fusion and
rendering, the live engine headless), the ARMadillo VST3 and LV2 plugins, the
standalone app and the Pure Data objects [armadillo] and [armadillo~]. A simulated forearm and OSC input (phone apps, NGIMU) let
it play without the hardware.")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)

set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)              # armadillo_<version>_<arch>.deb
set(CPACK_DEBIAN_PACKAGE_RELEASE "")
set(CPACK_DEBIAN_PACKAGE_SECTION sound)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# Beside what dpkg-shlibdeps finds: liblouis needs its tables at run time (a data package no
# library links), and JUCE opens the X11 libraries with dlopen() when the app or a plugin window
# opens, so no binary names them.
set(CPACK_DEBIAN_PACKAGE_DEPENDS "liblouis-data, libx11-6, libxext6, libxinerama1, libxrandr2, libxcursor1, libxrender1")
# A reader alone (docs/ACCESSIBILITY.md): speech and braille displays are opened with dlopen()
# only when asked for (--speak, --brlapi), so they are recommended, not required.
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "libspeechd2 | espeak-ng, libbrlapi0.8")
# Pure Data's [armadillo] and [armadillo~] (lib/pd/extra/armadillo) need a Pd to load them.
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "puredata-core | puredata")
set(CPACK_DEBIAN_PACKAGE_HOMEPAGE "https://armadillo.invalid")
set(CPACK_DEBIAN_PACKAGE_GENERATE_SHLIBS OFF)
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
set(CPACK_GENERATOR DEB)
include(CPack)
