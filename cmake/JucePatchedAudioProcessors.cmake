# One-line fix of Debian's JUCE 7.0.5 juce_audio_processors module, applied to a copy in the build
# tree at configure time (docs/PLUGIN.md, "Audio input"); everything else of JUCE is used exactly
# as Debian ships it.
#
# The problem: ClientBufferMapperData<FloatType>::setUpInputChannels() in
# format_types/juce_VST3Common.h, run by the VST3 wrapper on every processing block, takes each
# input bus's DynamicChannelMapping by value (`const auto mapping = map[busIndex];`), copying its
# std::vector of channel indices: a heap allocation on the audio thread per block whenever the
# plugin declares an input bus. JUCE fixed it later by taking a reference
# (`const auto& mapping = map[busIndex];`, as the same file's setUpOutputChannels() already does);
# this applies exactly that change.
#
# Loud failure: the Debian file must be byte-for-byte the one this patch was written against
# (its SHA-256 below) and hold the line exactly once; anything else stops the configuration with
# an explanation instead of silently building an unpatched (allocating) or mispatched wrapper.
#
# Use: armadillo_patch_juce_audio_processors(<targets...>) after find_package(JUCE) and
# juce_add_plugin(): the module's sources are compiled from the copy, and the given targets (the
# shared code and every format target) find <juce_audio_processors/...> in the copy first.

set(ARMADILLO_JUCE_VST3COMMON_SHA256 "bd22209c331dda6a1bc7eab610a440a581bf24058db16fab9312563893bb80ac")
set(ARMADILLO_JUCE_VST3COMMON_OLD "            const auto mapping = map[busIndex];\n")
set(ARMADILLO_JUCE_VST3COMMON_NEW "            const auto& mapping = map[busIndex];   // ARMadillo: no copy (an allocation) per block, as newer JUCE\n")

function(armadillo_patch_juce_audio_processors)
    get_target_property(_modules juce_audio_processors INTERFACE_JUCE_MODULE_PATH)
    set(_original "${_modules}/juce_audio_processors")
    set(_file "${_original}/format_types/juce_VST3Common.h")
    if(NOT EXISTS "${_file}")
        message(FATAL_ERROR "JUCE patch: ${_file} not found; the Debian JUCE module layout changed. "
                            "Check cmake/JucePatchedAudioProcessors.cmake against the installed JUCE.")
    endif()
    file(SHA256 "${_file}" _hash)
    if(NOT _hash STREQUAL ARMADILLO_JUCE_VST3COMMON_SHA256)
        message(FATAL_ERROR "JUCE patch: ${_file} is not the file the patch was written for "
                            "(SHA-256 ${_hash}, expected ${ARMADILLO_JUCE_VST3COMMON_SHA256}). "
                            "Debian's JUCE changed: check whether ClientBufferMapperData::setUpInputChannels "
                            "still copies each bus's channel mapping per block, then update or drop "
                            "cmake/JucePatchedAudioProcessors.cmake (docs/PLUGIN.md, \"Audio input\").")
    endif()
    file(READ "${_file}" _text)
    string(FIND "${_text}" "${ARMADILLO_JUCE_VST3COMMON_OLD}" _first)
    string(FIND "${_text}" "${ARMADILLO_JUCE_VST3COMMON_OLD}" _last REVERSE)
    if(_first EQUAL -1 OR NOT _first EQUAL _last)
        message(FATAL_ERROR "JUCE patch: the line to fix is not in ${_file} exactly once.")
    endif()

    set(_root "${CMAKE_BINARY_DIR}/juce-patched")
    set(_copy "${_root}/juce_audio_processors")
    file(REMOVE_RECURSE "${_copy}")
    file(COPY "${_original}" DESTINATION "${_root}")
    string(REPLACE "${ARMADILLO_JUCE_VST3COMMON_OLD}" "${ARMADILLO_JUCE_VST3COMMON_NEW}" _patched "${_text}")
    file(WRITE "${_copy}/format_types/juce_VST3Common.h" "${_patched}")
    # Reconfigure when the Debian file changes (the check above runs again).
    set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS "${_file}")

    # The module's translation units from the copy.
    get_target_property(_sources juce_audio_processors INTERFACE_SOURCES)
    set(_moved)
    foreach(_s IN LISTS _sources)
        string(REPLACE "${_original}/" "${_copy}/" _m "${_s}")
        list(APPEND _moved "${_m}")
    endforeach()
    if(_moved STREQUAL _sources)
        message(FATAL_ERROR "JUCE patch: no juce_audio_processors source was found under ${_original}.")
    endif()
    set_property(TARGET juce_audio_processors PROPERTY INTERFACE_SOURCES "${_moved}")
    # Every #include <juce_audio_processors/...> (the VST3 wrapper's among them) from the copy.
    foreach(_t IN LISTS ARGN)
        if(TARGET ${_t})
            target_include_directories(${_t} BEFORE PRIVATE "${_root}")
        endif()
    endforeach()
    message(STATUS "JUCE patch: juce_audio_processors compiled from ${_copy} (VST3 input buses without a per-block copy)")
endfunction()
