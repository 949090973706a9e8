#pragma once
/// @file gl.hpp  Small OpenGL helpers: error checks that name where they failed, shader programs
/// whose compile and link logs become the error message, and owning handles for GL objects.
/// Functions come from libepoxy, which loads them from the current context.

#include <epoxy/gl.h>

#include <stdexcept>
#include <string>
#include <utility>

namespace radiosity::view::gl {

/// A GL call failed: the message names the place and the errors.
class Error : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

/// Throws gl::Error naming `where` and every pending GL error (glGetError), if there is one.
void check(const char* where);

/// Compiles and links a program from GLSL sources; throws gl::Error with the compiler's or the
/// linker's log, naming the program.
GLuint program(const char* vertex_source, const char* fragment_source, const std::string& name);

/// An owned GL object name, deleted with Delete(name) when the handle goes.
template <void (*Delete)(GLuint)>
class Handle {
  public:
    Handle() = default;
    explicit Handle(GLuint id) : id_(id) {}
    Handle(Handle&& o) noexcept : id_(std::exchange(o.id_, 0)) {}
    Handle& operator=(Handle&& o) noexcept {
        if (this != &o) {
            reset();
            id_ = std::exchange(o.id_, 0);
        }
        return *this;
    }
    Handle(const Handle&) = delete;
    Handle& operator=(const Handle&) = delete;
    ~Handle() { reset(); }
    GLuint get() const { return id_; }  ///< the GL name (0: none)
    void reset() {
        if (id_ != 0) Delete(id_);
        id_ = 0;
    }

  private:
    GLuint id_ = 0;
};

void delete_buffer(GLuint id);        ///< glDeleteBuffers of one name
void delete_texture(GLuint id);       ///< glDeleteTextures of one name
void delete_framebuffer(GLuint id);   ///< glDeleteFramebuffers of one name
void delete_vertex_array(GLuint id);  ///< glDeleteVertexArrays of one name
void delete_program(GLuint id);       ///< glDeleteProgram

using Buffer = Handle<delete_buffer>;             ///< a buffer object
using Texture = Handle<delete_texture>;           ///< a texture
using Framebuffer = Handle<delete_framebuffer>;   ///< a framebuffer object
using VertexArray = Handle<delete_vertex_array>;  ///< a vertex array object
using Program = Handle<delete_program>;           ///< a linked program

Buffer make_buffer();             ///< a new buffer name
Texture make_texture();           ///< a new texture name
Framebuffer make_framebuffer();   ///< a new framebuffer name
VertexArray make_vertex_array();  ///< a new vertex array name

/// Fills a 2D RGBA8 texture (rows top first as given; nearest filtering, clamped) for ImGui.
void upload_rgba(GLuint texture, int width, int height, const void* pixels);

}  // namespace radiosity::view::gl
