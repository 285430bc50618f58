# What the two embedding scripts share (cmake/EmbedResources.cmake: the core's data files,
# cmake/EmbedWeb.cmake: the web page's files): a file as a C++ byte array, and a generated source
# rewritten only when it changed (so a reconfigure does not rebuild what includes it).

# Appends `const unsigned char <name>[] = {…};` with the bytes of `path` to the variable `out`,
# and sets `size_var` to the file's size. One byte more than the file (a terminating 0), so an
# empty file is still a valid array.
function(embed_bytes path name out size_var)
    file(READ "${path}" _hex HEX)
    file(SIZE "${path}" _size)
    string(REGEX REPLACE "([0-9a-f][0-9a-f])" "0x\\1," _bytes "${_hex}")
    string(REGEX REPLACE "(0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,0x..,)" "\\1\n" _bytes "${_bytes}")
    set(${out} "${${out}}const unsigned char ${name}[] = {\n${_bytes}0};\n" PARENT_SCOPE)
    set(${size_var} ${_size} PARENT_SCOPE)
endfunction()

# Writes `content` to `output` unless it already holds exactly that.
function(write_if_changed output content)
    if(EXISTS "${output}")
        file(READ "${output}" _old)
        if(_old STREQUAL content)
            return()
        endif()
    endif()
    file(WRITE "${output}" "${content}")
endfunction()
