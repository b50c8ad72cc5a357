// Shader programs compiled and linked once for every GL user (common/gl/gl_program.h), on a headless OSMesa context:
// a program that compiles and links is returned; a shader that does not compile throws a message naming the
// program, the stage and the compiler's log; a program that does not link names the program and carries the
// linker's log.
#include <gtest/gtest.h>

#include <glad/gl.h>

#include <memory>
#include <stdexcept>
#include <string>

#include "common/gl/gl_program.h"
#include "preprocess/gl/gl_context.h"

using namespace firstshot;

namespace {

const char* kVersion = "#version 450 core\n";
const char* kVertex = "void main() { gl_Position = vec4(0.0, 0.0, 0.0, 1.0); }\n";
const char* kFragment = "layout(location = 0) out vec4 colour;\nvoid main() { colour = vec4(1.0); }\n";

/// A current OSMesa context, or null with @p why set.
std::unique_ptr<GLContext> context(std::string& why) {
  try {
    return std::make_unique<GLContext>(GLBackend::OSMesa);
  } catch (const std::exception& e) {
    why = e.what();
    return nullptr;
  }
}

/// The message linkProgram throws for @p stages, or "" when it does not throw.
std::string failure(const std::vector<ShaderStage>& stages) {
  try {
    glDeleteProgram(linkProgram("test program", stages));
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return {};
}

}  // namespace

TEST(GLProgram, StageNames) {
  EXPECT_STREQ(shaderStageName(GL_VERTEX_SHADER), "vertex");
  EXPECT_STREQ(shaderStageName(GL_FRAGMENT_SHADER), "fragment");
  EXPECT_STREQ(shaderStageName(GL_COMPUTE_SHADER), "compute");
}

TEST(GLProgram, LinksAndNamesTheFailingStageWithItsLog) {
  std::string why;
  const std::unique_ptr<GLContext> gl = context(why);
  if (!gl) GTEST_SKIP() << "no OpenGL here (OSMesa context failed): " << why;

  // Parts are concatenated in order: the version line apart from the body.
  const unsigned program = linkProgram("test program", {{GL_VERTEX_SHADER, {kVersion, kVertex}},
                                                        {GL_FRAGMENT_SHADER, {kVersion, kFragment}}});
  EXPECT_NE(program, 0u);
  GLint linked = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &linked);
  EXPECT_TRUE(linked);
  glDeleteProgram(program);
  const unsigned compute = linkProgram(
      "test program", {{GL_COMPUTE_SHADER, {kVersion, "layout(local_size_x = 1) in;\nvoid main() {}\n"}}});
  EXPECT_NE(compute, 0u);
  glDeleteProgram(compute);

  // A fragment shader with an undeclared name: the stage and the compiler's log (which names the identifier).
  const char* undeclared = "out vec4 c;\nvoid main() { c = undeclaredName; }\n";
  const std::string bad =
      failure({{GL_VERTEX_SHADER, {kVersion, kVertex}}, {GL_FRAGMENT_SHADER, {kVersion, undeclared}}});
  EXPECT_NE(bad.find("test program: the fragment shader does not compile: "), std::string::npos) << bad;
  EXPECT_NE(bad.find("undeclaredName"), std::string::npos) << bad;

  // The vertex stage, with a syntax error.
  const std::string badVertex = failure({{GL_VERTEX_SHADER, {kVersion, "void main() { gl_Position = ; }\n"}},
                                         {GL_FRAGMENT_SHADER, {kVersion, kFragment}}});
  EXPECT_NE(badVertex.find("test program: the vertex shader does not compile: "), std::string::npos) << badVertex;
  EXPECT_EQ(badVertex.find("(no log)"), std::string::npos) << badVertex;

  // Each stage compiles, the program does not link: a vertex shader without main().
  const std::string unlinked = failure({{GL_VERTEX_SHADER, {kVersion, "float f() { return 1.0; }\n"}},
                                        {GL_FRAGMENT_SHADER, {kVersion, kFragment}}});
  EXPECT_NE(unlinked.find("test program: the program does not link: "), std::string::npos) << unlinked;
  EXPECT_EQ(unlinked.find("(no log)"), std::string::npos) << unlinked;
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}
