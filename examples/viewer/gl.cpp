// OpenGL helpers (gl.hpp).
#include "gl.hpp"

#include <algorithm>
#include <vector>

namespace radiosity::view::gl {

namespace {
const char* error_name(GLenum e) {
    switch (e) {
        case GL_INVALID_ENUM:
            return "GL_INVALID_ENUM";
        case GL_INVALID_VALUE:
            return "GL_INVALID_VALUE";
        case GL_INVALID_OPERATION:
            return "GL_INVALID_OPERATION";
        case GL_INVALID_FRAMEBUFFER_OPERATION:
            return "GL_INVALID_FRAMEBUFFER_OPERATION";
        case GL_OUT_OF_MEMORY:
            return "GL_OUT_OF_MEMORY";
        default:
            return "unknown GL error";
    }
}

/// The info log of a shader or program object (what the driver says of a failed compile or
/// link), through the matching pair of getters: glGetShaderiv/glGetShaderInfoLog or
/// glGetProgramiv/glGetProgramInfoLog.
template <class GetLength, class GetLog>
std::string info_log(GLuint object, GetLength get_length, GetLog get_log) {
    GLint length = 0;
    get_length(object, GL_INFO_LOG_LENGTH, &length);
    std::vector<char> log(static_cast<std::size_t>(std::max(length, 1)));
    get_log(object, length, nullptr, log.data());
    return log.data();
}

GLuint shader(GLenum kind, const char* source, const std::string& name) {
    const GLuint s = glCreateShader(kind);
    glShaderSource(s, 1, &source, nullptr);
    glCompileShader(s);
    GLint ok = GL_FALSE;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (ok != GL_TRUE) {
        const std::string log = info_log(s, glGetShaderiv, glGetShaderInfoLog);
        glDeleteShader(s);
        throw Error(name + (kind == GL_VERTEX_SHADER ? " vertex" : " fragment") +
                    " shader does not compile: " + log);
    }
    return s;
}
}  // namespace

void check(const char* where) {
    std::string errors;
    for (GLenum e = glGetError(); e != GL_NO_ERROR; e = glGetError())
        errors += std::string(errors.empty() ? "" : ", ") + error_name(e);
    if (!errors.empty()) throw Error(std::string("OpenGL error in ") + where + ": " + errors);
}

GLuint program(const char* vertex_source, const char* fragment_source, const std::string& name) {
    const GLuint vs = shader(GL_VERTEX_SHADER, vertex_source, name);
    const GLuint fs = shader(GL_FRAGMENT_SHADER, fragment_source, name);
    const GLuint p = glCreateProgram();
    glAttachShader(p, vs);
    glAttachShader(p, fs);
    glLinkProgram(p);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = GL_FALSE;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    if (ok != GL_TRUE) {
        const std::string log = info_log(p, glGetProgramiv, glGetProgramInfoLog);
        glDeleteProgram(p);
        throw Error(name + " program does not link: " + log);
    }
    check(("linking the " + name + " program").c_str());
    return p;
}

void delete_buffer(GLuint id) {
    glDeleteBuffers(1, &id);
}
void delete_texture(GLuint id) {
    glDeleteTextures(1, &id);
}
void delete_framebuffer(GLuint id) {
    glDeleteFramebuffers(1, &id);
}
void delete_vertex_array(GLuint id) {
    glDeleteVertexArrays(1, &id);
}
void delete_program(GLuint id) {
    glDeleteProgram(id);
}

Buffer make_buffer() {
    GLuint id = 0;
    glGenBuffers(1, &id);
    return Buffer(id);
}
Texture make_texture() {
    GLuint id = 0;
    glGenTextures(1, &id);
    return Texture(id);
}
Framebuffer make_framebuffer() {
    GLuint id = 0;
    glGenFramebuffers(1, &id);
    return Framebuffer(id);
}
VertexArray make_vertex_array() {
    GLuint id = 0;
    glGenVertexArrays(1, &id);
    return VertexArray(id);
}

void upload_rgba(GLuint texture, int width, int height, const void* pixels) {
    glBindTexture(GL_TEXTURE_2D, texture);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, pixels);
    glBindTexture(GL_TEXTURE_2D, 0);
    check("uploading a picture");
}

}  // namespace radiosity::view::gl
