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
      mesh_({3, 3, 3, 1}),
      fragments_({3, 4}),
      lines_({3, 4}),
      linesOnTop_({3, 4}),
      imageQuads_({2, 2}) {}

void SceneRenderer::setScene(const Scene& scene) {
    std::vector<float> data;
    const vis::PolygonMesh& mesh = scene.mesh;
    for (uint32_t f = 0; f < scene.faceCount(); ++f) {
        const auto face = mesh.face(f);
        if (face.size() < 3) continue;
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
            for (const uint32_t v : {face[0], face[j], face[j + 1]}) {
                const Vec3 p = mesh.vertices[v];
                data.insert(data.end(), {static_cast<float>(p.x), static_cast<float>(p.y),
                                         static_cast<float>(p.z), static_cast<float>(n.x),
                                         static_cast<float>(n.y), static_cast<float>(n.z),
                                         static_cast<float>(colour.x), static_cast<float>(colour.y),
                                         static_cast<float>(colour.z), emissive});
            }
        }
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
    mesh_.draw(GL_TRIANGLES);
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
