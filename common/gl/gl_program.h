#pragma once
/// @file gl_program.h
/// OpenGL shader programs compiled and linked, written once for the tools' GL users (preprocess/gl/gl_item_buffer.cpp,
/// preprocess/gl/gl_reduce.cpp, render/preview/gl_raster.cpp). Built into its own library, firstshot_gl, which only
/// they link: firstshot_common needs no OpenGL. The calls need a current context whose functions glad has loaded.
#include <string>
#include <vector>

namespace firstshot {

/// One stage of a program: its GL shader type and its source as parts that GL concatenates in order (e.g. a version
/// line, defines, the body).
struct ShaderStage {
  unsigned type = 0;               ///< GL_VERTEX_SHADER, GL_FRAGMENT_SHADER, GL_COMPUTE_SHADER, …
  std::vector<const char*> parts;  ///< null-terminated source parts
};

/// Compiles @p stages and links them into a program; returns its GL name (the caller deletes it with
/// glDeleteProgram). On failure nothing is left allocated.
/// @param what names the program in messages, e.g. "GL item buffer"
/// @throws std::runtime_error "<what>: the <stage> shader does not compile: <its info log>" (stage: vertex,
///         fragment, compute, …) or "<what>: the program does not link: <the program's info log>"
unsigned linkProgram(const std::string& what, const std::vector<ShaderStage>& stages);

/// The name of a GL shader type in messages: "vertex", "fragment", "compute", …
const char* shaderStageName(unsigned type);

}  // namespace firstshot
