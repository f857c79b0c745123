// SceneRenderer: draws the scene mesh (flat shading, area lights emissive, base-colour textures on
// the faces that have coordinates for them) and the debug overlays
// into a rectangle of the current framebuffer, through the GL function table
// (app/viewer/gl/gl_api.h). Create, use and destroy it with one GL context's table current.
// GL code only: the viewer hands it a camera, vertex arrays and colours, never its own state.
#pragma once

#include <array>
#include <memory>
#include <span>
#include <vector>

#include "app/viewer/gl/shader_program.h"
#include "app/viewer/gl/vertex_buffer.h"
#include "app/viewer/viewport.h"
#include "engine/scene/camera.h"
#include "engine/scene/scene.h"

namespace penumbra::viewer {

// The column-major view-projection matrix matching Camera::project for a viewport of this size:
// a world point lands on the pixel that Camera::project computes.
std::array<float, 16> viewProjection(const Camera& camera, int width, int height,
                                     double nearDistance, double farDistance);

// The rendered view: the renderer's image shown in the 3D view instead of the rasterised colours,
// as vertical bands of the view, each filled by a horizontal range of the texture (one band for an
// image of the view's size; two for the split of exact and sampled images laid side by side in one
// texture). Texture rows from the top, as the renderer writes them.
struct ViewImage {
    GLuint texture = 0;
    struct Band {
        float x0 = 0, x1 = 1;  // of the view's width
        float u0 = 0, u1 = 1;  // of the texture's width
    };
    std::vector<Band> bands;
};

class SceneRenderer {
  public:
    // background: the colour behind the scene (linear RGB in [0, 1], as glClearColor takes it).
    explicit SceneRenderer(const std::array<float, 3>& background);
    ~SceneRenderer();  // deletes the scene's textures
    SceneRenderer(const SceneRenderer&) = delete;
    SceneRenderer& operator=(const SceneRenderer&) = delete;
    // The scene's faces (and no overlays), each textured material's faces in a draw of their own
    // with its image as a GL texture (sRGB texels, its wrap and filter; no mipmaps), the texture
    // coordinates transformed on upload (UvTransform is affine, so the GPU's interpolation of the
    // transformed corners is the transform of the interpolated coordinates: the fan of
    // engine/scene/face_uv.h, as the renderer reads it).
    void setScene(const Scene& scene);
    // The overlays, x y z r g b a per vertex: triangles depth-tested and pulled forward onto the
    // light's plane, lines depth-tested, lines drawn over everything (OverlayGeometry's three
    // arrays).
    void setOverlay(std::span<const float> fragmentTriangles, std::span<const float> lines,
                    std::span<const float> linesOnTop);
    void clearOverlay() { setOverlay({}, {}, {}); }
    // Clears the viewport and draws the view of `camera`, whose GL projection clips at
    // nearDistance and farDistance; framebufferHeight converts to GL's bottom-up rows. With an
    // image, the mesh only fills the depth buffer and the image is drawn in its place, pixel for
    // pixel; the overlays are drawn on top of either, depth-tested against the mesh.
    void draw(const Camera& camera, double nearDistance, double farDistance,
              const Viewport& viewport, int framebufferHeight,
              const ViewImage* image = nullptr) const;

  private:
    void drawImage(const ViewImage& image) const;

    // A range of mesh_'s vertices drawn with one texture (0: none).
    struct MeshBatch {
        size_t first = 0, count = 0;
        GLuint texture = 0;
    };
    void deleteTextures();

    std::array<float, 3> background_;
    ShaderProgram meshProgram_, overlayProgram_, imageProgram_;
    std::vector<MeshBatch> batches_;
    std::vector<GLuint> textures_;  // owned
    VertexBuffer mesh_, fragments_, lines_, linesOnTop_;
    mutable VertexBuffer imageQuads_;
};

}  // namespace penumbra::viewer
