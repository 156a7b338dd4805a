#include "tools/viewer/gl_scene.h"

#include <stdexcept>
#include <string>

namespace xcut::viewer {

namespace {

const char* kVertex = R"(#version 330 core
layout(location = 0) in vec3 p;
layout(location = 2) in vec3 c;
uniform mat4 mvp;
out vec3 vp;
out vec3 vc;
void main() { vp = p; vc = c; gl_Position = mvp * vec4(p, 1.0); }
)";

// engine/io/render.cpp's shading: 0.25 + 0.75 max(0, n.l), with the triangle's own (flat) normal,
// here from the derivatives of the position across the pixel, turned towards the eye.
const char* kFragment = R"(#version 330 core
in vec3 vp;
in vec3 vc;
uniform vec3 eye;
uniform vec3 light;
uniform int lit;
out vec4 colour;
void main() {
    vec3 c = vc;
    if (lit == 1) {
        vec3 n = normalize(cross(dFdx(vp), dFdy(vp)));
        if (dot(n, vp - eye) > 0.0) n = -n;
        c *= 0.25 + 0.75 * max(0.0, dot(n, light));
    }
    colour = vec4(c, 1.0);
}
)";

GLuint compile(GLenum kind, const char* source) {
    const GLuint s = glCreateShader(kind);
    glShaderSource(s, 1, &source, nullptr);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[1024];
        glGetShaderInfoLog(s, sizeof(log), nullptr, log);
        throw std::runtime_error(std::string("OpenGL: a viewer shader did not compile: ") + log);
    }
    return s;
}

constexpr float kSkin[3] = {0.93f, 0.76f, 0.66f}, kWound[3] = {0.80f, 0.12f, 0.12f};

void vertex(std::vector<float>& out, const Vec3& p, const float* c) {
    out.insert(out.end(), {float(p.x()), float(p.y()), float(p.z()), c[0], c[1], c[2]});
}

void triangles(std::vector<float>& out, const std::vector<Vec3>& v, const std::vector<std::array<int, 3>>& tris,
               const float* colour) {
    for (const auto& t : tris) vertex(out, v[t[0]], colour), vertex(out, v[t[1]], colour), vertex(out, v[t[2]], colour);
}

void lines(std::vector<float>& out, const std::vector<Vec3>& pairs, const float* colour) {
    for (const Vec3& p : pairs) vertex(out, p, colour);
}

}  // namespace

GlScene::GlScene() {
    const GLuint vs = compile(GL_VERTEX_SHADER, kVertex), fs = compile(GL_FRAGMENT_SHADER, kFragment);
    program_ = glCreateProgram();
    glAttachShader(program_, vs);
    glAttachShader(program_, fs);
    glLinkProgram(program_);
    glDeleteShader(vs);
    glDeleteShader(fs);
    mvp_ = glGetUniformLocation(program_, "mvp");
    eye_ = glGetUniformLocation(program_, "eye");
    light_ = glGetUniformLocation(program_, "light");
    lit_ = glGetUniformLocation(program_, "lit");
    surface_.indexed = true;
    for (Batch* b : {&surface_, &shapes_, &lines_}) {
        glGenVertexArrays(1, &b->vao);
        glGenBuffers(1, &b->vbo);
        glBindVertexArray(b->vao);
        glBindBuffer(GL_ARRAY_BUFFER, b->vbo);
        glEnableVertexAttribArray(0);
        glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
        if (b->indexed) {  // the colour: a constant attribute, set per run
            glGenBuffers(1, &b->ebo);
            glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, b->ebo);
        } else {
            glEnableVertexAttribArray(2);
            glVertexAttribPointer(2, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), reinterpret_cast<void*>(3 * sizeof(float)));
        }
    }
    glBindVertexArray(0);
    lines_.mode = GL_LINES, lines_.lit = false;
}

GlScene::~GlScene() {
    for (Batch* b : {&surface_, &shapes_, &lines_}) {
        glDeleteBuffers(1, &b->vbo);
        if (b->ebo) glDeleteBuffers(1, &b->ebo);
        glDeleteVertexArrays(1, &b->vao);
    }
    glDeleteProgram(program_);
}

void GlScene::fill(Batch& b, const std::vector<float>& data) {
    glBindBuffer(GL_ARRAY_BUFFER, b.vbo);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(data.size() * sizeof(float)), data.data(), GL_STREAM_DRAW);
    b.count = static_cast<GLsizei>(data.size() / 6);
}

void GlScene::upload(const Snapshot& s, const Overlays& show) {
    static constexpr float kTool[3] = {0.55f, 0.60f, 0.68f}, kMesh[3] = {0.35f, 0.35f, 0.40f},
                           kVirtual[3] = {0.10f, 0.45f, 0.85f}, kQuad[3] = {0.95f, 0.65f, 0.05f},
                           kContact[3] = {0.05f, 0.65f, 0.25f}, kForce[3] = {0.85f, 0.05f, 0.65f},
                           kBlade[3] = {0.10f, 0.10f, 0.12f};
    closed_ = s.dim3;
    vertices_.clear(), indices_.clear();  // the surface: its vertices once, skin triangles first
    for (const Vec3& p : s.surface) vertex(vertices_, p, kSkin);
    for (int wound = 0; wound < 2; ++wound) {
        if (wound == 1) surface_.skin = static_cast<GLsizei>(indices_.size());
        for (size_t t = 0; t < s.triangles.size(); ++t)
            if ((t < s.cut_face.size() && s.cut_face[t]) == (wound == 1))
                for (int k : s.triangles[t]) indices_.push_back(static_cast<unsigned>(k));
    }
    glBindVertexArray(surface_.vao);
    fill(surface_, vertices_);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(indices_.size() * sizeof(unsigned)), indices_.data(),
                 GL_STREAM_DRAW);
    glBindVertexArray(0);
    surface_.count = static_cast<GLsizei>(indices_.size());
    std::vector<float>& data = vertices_;
    data.clear();
    if (show.tools)
        for (const ToolView& t : s.tools) triangles(data, t.shape_vertices, t.shape_triangles, kTool);
    fill(shapes_, data);
    data.clear();
    if (show.mesh) lines(data, s.mesh_lines, kMesh);
    if (show.virtuals) lines(data, s.virtual_lines, kVirtual);
    if (show.quad) lines(data, s.quad_lines, kQuad);
    double scale = 0.0;  // contact normals and force arrows in proportion to the surface
    for (const Vec3& p : s.surface) scale = std::max(scale, (p - s.surface.front()).norm());
    if (show.contacts)
        for (size_t c = 0; c < s.contact_points.size(); ++c) {
            const std::vector<Vec3> seg = {s.contact_points[c], s.contact_points[c] + 0.02 * scale * s.contact_normals[c]};
            lines(data, seg, kContact);
        }
    for (const ToolView& t : s.tools) {
        if (show.tools && t.blade) lines(data, {t.tip, t.heel}, kBlade);
        const double f = t.force.norm();
        if (!show.force || !(f > 1e-9)) continue;
        const Vec3 tip = t.position + 0.1 * scale * std::min(1.0, 0.2 + f) * t.force / f;  // length grows to 1 N
        const Vec3 side = t.force.unitOrthogonal() * 0.015 * scale, back = tip - 0.03 * scale * t.force / f;
        lines(data, {t.position, tip, tip, back + side, tip, back - side}, kForce);
    }
    fill(lines_, data);
}

void GlScene::draw(const OrbitCamera& camera, int width, int height) const {
    glViewport(0, 0, width, height);
    glClearColor(235 / 255.f, 238 / 255.f, 242 / 255.f, 1.f);  // the renderer's background
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glUseProgram(program_);
    const Eigen::Matrix4f mvp = camera.projection(double(width) / std::max(height, 1)) * camera.view();
    glUniformMatrix4fv(mvp_, 1, GL_FALSE, mvp.data());
    glUniform3f(eye_, float(camera.position.x()), float(camera.position.y()), float(camera.position.z()));
    const Vec3 light = Vec3(0.4, -0.3, 1.0).normalized();
    glUniform3f(light_, float(light.x()), float(light.y()), float(light.z()));
    for (const Batch* b : {&surface_, &shapes_, &lines_}) {
        if (b->count == 0) continue;
        if (b == &surface_) {
            if (closed_) glEnable(GL_CULL_FACE);  // a closed outward surface: its back faces never show
            else glDisable(GL_CULL_FACE);         // a 2D sheet shows both faces
            glEnable(GL_POLYGON_OFFSET_FILL);  // behind the mesh lines drawn on it, not fighting them
            glPolygonOffset(1.f, 1.f);
        } else {
            glDisable(GL_CULL_FACE);
            glDisable(GL_POLYGON_OFFSET_FILL);
        }
        glUniform1i(lit_, b->lit ? 1 : 0);
        glBindVertexArray(b->vao);
        if (!b->indexed) {
            glDrawArrays(b->mode, 0, b->count);
            continue;
        }
        glVertexAttrib3fv(2, kSkin);
        glDrawElements(GL_TRIANGLES, b->skin, GL_UNSIGNED_INT, nullptr);
        glVertexAttrib3fv(2, kWound);
        glDrawElements(GL_TRIANGLES, b->count - b->skin, GL_UNSIGNED_INT,
                       reinterpret_cast<void*>(static_cast<uintptr_t>(b->skin) * sizeof(unsigned)));
    }
    glBindVertexArray(0);
}

Image read_framebuffer(int width, int height) {
    Image img;
    img.width = width, img.height = height;
    std::vector<unsigned char> rows(3 * width * height);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, rows.data());
    img.rgb.resize(rows.size());
    for (int r = 0; r < height; ++r)  // GL's first row is the bottom one
        std::copy_n(&rows[3 * width * (height - 1 - r)], 3 * width, &img.rgb[3 * width * r]);
    return img;
}

}  // namespace xcut::viewer
