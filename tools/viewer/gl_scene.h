#pragma once
// OpenGL 3.3 core drawing of a snapshot: the visual surface Lambert-shaded exactly as the headless
// renderer shades it (engine/io/render.cpp: the same light, ambient term, two-sided normals, skin and
// wound colours), tool shapes, and line overlays (mesh, virtual elements, collision quads, contacts,
// blades, reaction forces). Needs a current GL context (libepoxy resolves the entry points).
#include <epoxy/gl.h>

#include <vector>

#include "tools/viewer/orbit_camera.h"
#include "tools/viewer/snapshot.h"

namespace xcut::viewer {

struct Overlays {
    bool tools = true, mesh = false, virtuals = false, quad = true, contacts = true, force = true;
    bool operator==(const Overlays&) const = default;
};

class GlScene {
public:
    GlScene();
    ~GlScene();
    GlScene(const GlScene&) = delete;
    GlScene& operator=(const GlScene&) = delete;
    /// Rebuilds the vertex buffers from a new snapshot.
    void upload(const Snapshot& s, const Overlays& show);
    /// Clears to the renderer's background and draws.
    void draw(const OrbitCamera& camera, int width, int height) const;

private:
    /// Vertices of 6 floats (position, colour); the surface's are its own, shared by its triangles
    /// and drawn by index in two runs (skin, then wound), each run in one colour.
    struct Batch {
        GLuint vao = 0, vbo = 0, ebo = 0;
        GLsizei count = 0;      ///< vertices, or indices of an indexed batch
        GLsizei skin = 0;       ///< indexed: the first `skin` indices are skin, the rest wound
        GLenum mode = GL_TRIANGLES;
        bool lit = true, indexed = false;
    };
    void fill(Batch& b, const std::vector<float>& data);
    GLuint program_ = 0;
    GLint mvp_ = -1, eye_ = -1, light_ = -1, lit_ = -1;
    Batch surface_, shapes_, lines_;
    std::vector<float> vertices_;    ///< upload buffers, kept to reuse their memory
    std::vector<unsigned> indices_;
    bool closed_ = true;             ///< the surface is closed (3D): back faces culled
};

/// The window's colour buffer as an RGB image, top row first.
Image read_framebuffer(int width, int height);

}  // namespace xcut::viewer
