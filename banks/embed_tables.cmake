# Writes OUTPUT, a C++ file holding every banks/tables/*.yaml as a string, so that the
# daemon carries its device tables and cannot start with tables from another version.
# Run as: cmake -DOUTPUT=... -DINPUTS="a.yaml|b.yaml" -P embed_tables.cmake
string(REPLACE "|" ";" INPUTS "${INPUTS}")
set(content "// Generated from banks/tables/*.yaml by banks/embed_tables.cmake. Do not edit.\n")
string(APPEND content "#include \"banks/embedded_tables.hpp\"\n\nnamespace unima::banks {\n\n")
string(APPEND content "const std::vector<EmbeddedTable>& embedded_tables() {\n")
string(APPEND content "  static const std::vector<EmbeddedTable> tables = {\n")
foreach(input IN LISTS INPUTS)
  get_filename_component(name "${input}" NAME)
  file(READ "${input}" text)
  string(APPEND content "    {\"${name}\", R\"unima_table(${text})unima_table\"},\n")
endforeach()
string(APPEND content "  };\n  return tables;\n}\n\n}  // namespace unima::banks\n")
file(WRITE "${OUTPUT}.tmp" "${content}")
file(COPY_FILE "${OUTPUT}.tmp" "${OUTPUT}" ONLY_IF_DIFFERENT)
