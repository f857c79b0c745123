#include "app/viewer/gl/scene_renderer.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>
#include <numbers>

namespace penumbra::viewer {

std::array<float, 16> viewProjection(const Camera& camera, int width, int height,
                                     double nearDistance, double farDistance) {
    Vec3 right, trueUp, forward;
    camera.frame(right, trueUp, forward);
    // Built in double: scene coordinates can be large (the Cornell box is ~550 units).
    const glm::dvec3 eye(camera.eye.x, camera.eye.y, camera.eye.z);
    const glm::dvec3 f(forward.x, forward.y, forward.z);
    const glm::dvec3 u(trueUp.x, trueUp.y, trueUp.z);
    const glm::dmat4 view = glm::lookAt(eye, eye + f, u);
    const glm::dmat4 projection = glm::perspective(camera.fovYDegrees * std::numbers::pi / 180.0,
                                                   static_cast<double>(width) / std::max(height, 1),
                                                   nearDistance, farDistance);
    const glm::mat4 m(projection * view);
    std::array<float, 16> out{};
    std::copy(glm::value_ptr(m), glm::value_ptr(m) + 16, out.begin());
    return out;
}

SceneRenderer::SceneRenderer(const std::array<float, 3>& background)
    : background_(background),
      meshProgram_("mesh.vert", "mesh.frag"),
      overlayProgram_("overlay.vert", "overlay.frag"),
      imageProgram_("image.vert", "image.frag"),
      mesh_({3, 3, 3, 1, 2}),
      fragments_({3, 4}),
      lines_({3, 4}),
      linesOnTop_({3, 4}),
      imageQuads_({2, 2}) {}

SceneRenderer::~SceneRenderer() { deleteTextures(); }

void SceneRenderer::deleteTextures() {
    if (!textures_.empty())
        glDeleteTextures(static_cast<GLsizei>(textures_.size()), textures_.data());
    textures_.clear();
}

namespace scene_renderer_detail {

GLint glWrap(TextureWrap wrap) {
    switch (wrap) {
        case TextureWrap::ClampToEdge:
            return GL_CLAMP_TO_EDGE;
        case TextureWrap::MirroredRepeat:
            return GL_MIRRORED_REPEAT;
        case TextureWrap::Repeat:
            break;
    }
    return GL_REPEAT;
}

// The material's image as a texture with its wrap and filter (texels sRGB: sampled as linear).
GLuint uploadTexture(const TextureImage& image, const TextureRef& ref) {
    GLuint texture = 0;
    glGenTextures(1, &texture);
    glBindTexture(GL_TEXTURE_2D, texture);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);  // rows of 3 bytes a texel
    glTexImage2D(GL_TEXTURE_2D, 0, GL_SRGB8, image.width, image.height, 0, GL_RGB, GL_UNSIGNED_BYTE,
                 image.srgb.data());
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    const GLint filter = ref.filter == TextureFilter::Nearest ? GL_NEAREST : GL_LINEAR;
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filter);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, glWrap(ref.wrapU));
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, glWrap(ref.wrapV));
    glBindTexture(GL_TEXTURE_2D, 0);
    return texture;
}

}  // namespace scene_renderer_detail

void SceneRenderer::setScene(const Scene& scene) {
    deleteTextures();
    batches_.clear();
    const vis::PolygonMesh& mesh = scene.mesh;
    // The faces by what they are drawn with: no texture (slot 0), or material m's (slot m + 1)
    // when it has a map and the face has texture coordinates.
    std::vector<std::vector<uint32_t>> slots(scene.materials.size() + 1);
    for (uint32_t f = 0; f < scene.faceCount(); ++f) {
        if (mesh.face(f).size() < 3) continue;
        const int32_t m = f < scene.faceMaterial.size() ? scene.faceMaterial[f] : -1;
        const bool textured = m >= 0 && scene.materials[static_cast<size_t>(m)].kdMap.present() &&
                              !scene.materials[static_cast<size_t>(m)].isEmissive() &&
                              f < scene.faceUv.size() && !scene.faceUv[f].empty();
        slots[textured ? static_cast<size_t>(m) + 1 : 0].push_back(f);
    }
    std::vector<float> data;
    for (size_t slot = 0; slot < slots.size(); ++slot) {
        if (slots[slot].empty()) continue;
        MeshBatch batch;
        batch.first = data.size() / static_cast<size_t>(mesh_.stride());
        const TextureRef* map = slot > 0 ? &scene.materials[slot - 1].kdMap : nullptr;
        if (map != nullptr) {
            batch.texture = scene_renderer_detail::uploadTexture(
                scene.textures[static_cast<size_t>(map->image)], *map);
            textures_.push_back(batch.texture);
        }
        for (const uint32_t f : slots[slot]) {
            const auto face = mesh.face(f);
            const Material& m = scene.material(f);
            const Vec3 n = normalize(mesh.faceAreaNormal(f));
            Vec3 colour = m.kd;
            float emissive = 0;
            if (m.isEmissive()) {
                // The light's colour, normalised so that its brightest channel is 1.
                const double top = std::max({m.ke.x, m.ke.y, m.ke.z});
                colour = m.ke / top;
                emissive = 1;
            }
            for (size_t j = 1; j + 1 < face.size(); ++j) {
                for (const size_t k : {size_t{0}, j, j + 1}) {
                    const Vec3 p = mesh.vertices[face[k]];
                    Uv uv{0, 0};
                    if (map != nullptr) uv = map->transform.apply(scene.faceUv[f][k]);
                    data.insert(
                        data.end(),
                        {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z),
                         static_cast<float>(n.x), static_cast<float>(n.y), static_cast<float>(n.z),
                         static_cast<float>(colour.x), static_cast<float>(colour.y),
                         static_cast<float>(colour.z), emissive, static_cast<float>(uv.u),
                         static_cast<float>(uv.v)});
                }
            }
        }
        batch.count = data.size() / static_cast<size_t>(mesh_.stride()) - batch.first;
        batches_.push_back(batch);
    }
    mesh_.upload(data);
    clearOverlay();
}

void SceneRenderer::setOverlay(std::span<const float> fragmentTriangles,
                               std::span<const float> lines, std::span<const float> linesOnTop) {
    fragments_.upload(fragmentTriangles);
    lines_.upload(lines);
    linesOnTop_.upload(linesOnTop);
}

void SceneRenderer::drawImage(const ViewImage& image) const {
    // Two triangles per band, in the view's clip space (x from -1 at the left, y from -1 at the
    // bottom), texture v = 0 at the top row.
    std::vector<float> quads;
    for (const ViewImage::Band& b : image.bands) {
        const float x0 = 2 * b.x0 - 1, x1 = 2 * b.x1 - 1;
        quads.insert(quads.end(), {x0, -1, b.u0, 1, x1, -1, b.u1, 1, x1, 1, b.u1, 0,
                                   x0, -1, b.u0, 1, x1, 1,  b.u1, 0, x0, 1, b.u0, 0});
    }
    imageQuads_.upload(quads);
    glDisable(GL_DEPTH_TEST);
    glDepthMask(GL_FALSE);
    imageProgram_.use();
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, image.texture);
    imageQuads_.draw(GL_TRIANGLES);
    glBindTexture(GL_TEXTURE_2D, 0);
    glDepthMask(GL_TRUE);
    glEnable(GL_DEPTH_TEST);
}

void SceneRenderer::draw(const Camera& camera, double nearDistance, double farDistance,
                         const Viewport& vp, int framebufferHeight, const ViewImage* image) const {
    const int glY = framebufferHeight - (vp.y + vp.height);
    glViewport(vp.x, glY, vp.width, vp.height);
    glEnable(GL_SCISSOR_TEST);
    glScissor(vp.x, glY, vp.width, vp.height);
    glClearColor(background_[0], background_[1], background_[2], 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);
    glDepthMask(GL_TRUE);

    const std::array<float, 16> m =
        viewProjection(camera, vp.width, vp.height, nearDistance, farDistance);

    meshProgram_.use();
    meshProgram_.setMatrix("uViewProjection", m.data());
    meshProgram_.setVec3("uEye", static_cast<float>(camera.eye.x), static_cast<float>(camera.eye.y),
                         static_cast<float>(camera.eye.z));
    if (image != nullptr) glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);  // depth only
    glActiveTexture(GL_TEXTURE0);
    for (const MeshBatch& batch : batches_) {
        meshProgram_.setFloat("uTextured", batch.texture != 0 && image == nullptr ? 1.0f : 0.0f);
        glBindTexture(GL_TEXTURE_2D, batch.texture);
        mesh_.draw(GL_TRIANGLES, batch.first, batch.count);
    }
    glBindTexture(GL_TEXTURE_2D, 0);
    if (image != nullptr) {
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        drawImage(*image);
    }

    overlayProgram_.use();
    overlayProgram_.setMatrix("uViewProjection", m.data());
    overlayProgram_.setVec3("uEye", static_cast<float>(camera.eye.x),
                            static_cast<float>(camera.eye.y), static_cast<float>(camera.eye.z));
    overlayProgram_.setFloat("uPull", 0.0f);
    // The fragments lie in the light's plane: pulled forward a little to win the depth test, and
    // drawn only from the light's emitting side (they are counter-clockwise seen from there), so
    // that they never show through a ceiling seen from above. They write no depth: their edges
    // and the region's boundary, in the same plane, are tested against the scene's alone, moved
    // 3/10000 of their distance toward the eye (the offset does not reach lines; what lies closer
    // than that in front of the light, as a ceiling 0.8 above it seen from 2600 away, is drawn
    // over).
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(-1.0f, -2.0f);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    glFrontFace(GL_CCW);
    glDepthMask(GL_FALSE);
    fragments_.draw(GL_TRIANGLES);
    glDepthMask(GL_TRUE);
    glDisable(GL_CULL_FACE);
    glDisable(GL_POLYGON_OFFSET_FILL);
    overlayProgram_.setFloat("uPull", 3e-4f);
    lines_.draw(GL_LINES);
    overlayProgram_.setFloat("uPull", 0.0f);
    glDisable(GL_DEPTH_TEST);
    linesOnTop_.draw(GL_LINES);
    glUseProgram(0);
}

}  // namespace penumbra::viewer
