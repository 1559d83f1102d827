# Turns one SPIR-V file into a C++ source defining `NAMESPACE::SYMBOL` as a ShaderBinary (run with cmake -P).
file(READ ${SPIRV} bytes HEX)
string(LENGTH "${bytes}" hex_length)
math(EXPR word_count "${hex_length} / 8")
# SPIR-V is little-endian 32-bit words; regroup the byte stream into words.
string(REGEX REPLACE "(..)(..)(..)(..)" "0x\\4\\3\\2\\1u," words "${bytes}")
string(REGEX REPLACE "(([^,]*,){8})" "\\1\n    " words "${words}")
file(WRITE ${OUTPUT}
"// Generated from ${NAME}; do not edit.\n#include \"gpu/shader_binary.h\"\n\nnamespace ${NAMESPACE} {\nnamespace {\nconst uint32_t kWords[${word_count}] = {\n    ${words}\n};\n} // namespace\nextern const ssvgi::gpu::ShaderBinary ${SYMBOL};\nconst ssvgi::gpu::ShaderBinary ${SYMBOL}{\"${NAME}\", kWords};\n} // namespace ${NAMESPACE}\n")
