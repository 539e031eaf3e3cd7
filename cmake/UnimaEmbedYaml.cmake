# unima_embed_yaml(<out_var> DIRECTORY <dir> HEADER <h> NAMESPACE <ns> TYPE <t> FUNCTION <f> [GLOB <patterns>...])
# Generates a C++ source holding every <dir>/*.yaml, or every file matching GLOB (see
# embed_yaml.cmake), and sets <out_var> to its path, for a library's sources.
# Re-generated when a file changes.
set(UNIMA_EMBED_YAML_SCRIPT ${CMAKE_CURRENT_LIST_DIR}/embed_yaml.cmake)

function(unima_embed_yaml out_var)
  cmake_parse_arguments(ARG "" "DIRECTORY;HEADER;NAMESPACE;TYPE;FUNCTION" "GLOB" ${ARGN})
  if(NOT ARG_GLOB)
    set(ARG_GLOB "*.yaml")
  endif()
  list(TRANSFORM ARG_GLOB PREPEND "${ARG_DIRECTORY}/")
  file(GLOB files CONFIGURE_DEPENDS ${ARG_GLOB})
  list(SORT files)
  string(JOIN "|" file_list ${files})  # a ';' list would split the command line
  set(output ${CMAKE_CURRENT_BINARY_DIR}/${ARG_FUNCTION}.cpp)
  add_custom_command(
    OUTPUT ${output}
    COMMAND ${CMAKE_COMMAND} "-DOUTPUT=${output}" "-DINPUTS=${file_list}" "-DHEADER=${ARG_HEADER}"
            "-DNAMESPACE=${ARG_NAMESPACE}" "-DTYPE=${ARG_TYPE}" "-DFUNCTION=${ARG_FUNCTION}"
            -P ${UNIMA_EMBED_YAML_SCRIPT}
    DEPENDS ${files} ${UNIMA_EMBED_YAML_SCRIPT}
    COMMENT "Embedding ${ARG_DIRECTORY}: ${ARG_FUNCTION}"
    VERBATIM)
  set(${out_var} ${output} PARENT_SCOPE)
endfunction()
