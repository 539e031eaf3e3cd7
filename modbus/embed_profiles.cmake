# Writes OUTPUT, a C++ file holding every modbus/profiles/*.yaml as a string, so that the
# daemon and the simulator carry the same device profiles (as banks/embed_tables.cmake
# does for the device tables).
# Run as: cmake -DOUTPUT=... -DINPUTS="a.yaml|b.yaml" -P embed_profiles.cmake
string(REPLACE "|" ";" INPUTS "${INPUTS}")
set(content "// Generated from modbus/profiles/*.yaml by modbus/embed_profiles.cmake. Do not edit.\n")
string(APPEND content "#include \"modbus/embedded_profiles.hpp\"\n\nnamespace unima::modbus {\n\n")
string(APPEND content "const std::vector<EmbeddedProfile>& embedded_profiles() {\n")
string(APPEND content "  static const std::vector<EmbeddedProfile> profiles = {\n")
foreach(input IN LISTS INPUTS)
  get_filename_component(name "${input}" NAME)
  file(READ "${input}" text)
  string(APPEND content "    {\"${name}\", R\"unima_profile(${text})unima_profile\"},\n")
endforeach()
string(APPEND content "  };\n  return profiles;\n}\n\n}  // namespace unima::modbus\n")
file(WRITE "${OUTPUT}.tmp" "${content}")
file(COPY_FILE "${OUTPUT}.tmp" "${OUTPUT}" ONLY_IF_DIFFERENT)
