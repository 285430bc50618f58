# What `cmake --install` puts where (GNU layout under CMAKE_INSTALL_PREFIX). The binaries install
# from their own folders: Source/Cli (bin/armadillo, its man page) and Source/Plugin (VST3 in
# lib/vst3, LV2 in lib/lv2, the standalone app with its desktop entry and icon).
set(ARMADILLO_DOC_DIR ${CMAKE_INSTALL_DATAROOTDIR}/doc/armadillo)

# Debian's copyright file (the licences of everything in the binaries) and release notes.
install(FILES README.md CHANGELOG.md packaging/copyright DESTINATION ${ARMADILLO_DOC_DIR})
# The Debian changelog is required in every package's doc folder; compressed, like the man page.
# The package is native (version without a Debian revision), so its name is changelog.gz.
configure_file(packaging/changelog.Debian.in ${PROJECT_BINARY_DIR}/packaging/changelog @ONLY)
add_custom_command(
    OUTPUT ${PROJECT_BINARY_DIR}/packaging/changelog.gz
    COMMAND gzip -9nkf ${PROJECT_BINARY_DIR}/packaging/changelog
    DEPENDS ${PROJECT_BINARY_DIR}/packaging/changelog
    VERBATIM)
add_custom_target(armadillo_changelog ALL DEPENDS ${PROJECT_BINARY_DIR}/packaging/changelog.gz)
install(FILES ${PROJECT_BINARY_DIR}/packaging/changelog.gz DESTINATION ${ARMADILLO_DOC_DIR})

# The documentation (the README links into docs/) and the files its examples use.
install(DIRECTORY docs/ DESTINATION ${ARMADILLO_DOC_DIR}/docs)
install(DIRECTORY Resources/Examples/ DESTINATION ${ARMADILLO_DOC_DIR}/examples)
install(DIRECTORY Resources/Scores/ DESTINATION ${ARMADILLO_DOC_DIR}/examples/Scores)   # templates for your own
install(DIRECTORY Resources/Braille/ DESTINATION ${ARMADILLO_DOC_DIR}/examples/Braille)
