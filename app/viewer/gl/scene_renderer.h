// SceneRenderer: draws the scene mesh (flat shading, area lights emissive) and the debug overlays
// into a rectangle of the current framebuffer, through the GL function table
// (app/viewer/gl/gl_api.h). Create, use and destroy it with one GL context's table current.
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "app/viewer/gl/shader_program.h"
#include "app/viewer/gl/vertex_buffer.h"
#include "app/viewer/orbit_camera.h"
#include "app/viewer/overlay_geometry.h"
#include "engine/scene/scene.h"

namespace penumbra::viewer {

// A rectangle of the framebuffer in image coordinates (origin top-left, y down), the convention of
// Camera::project and of screenshots.
struct Viewport {
    int x = 0, y = 0, width = 1, height = 1;
    bool contains(double px, double py) const {
        return px >= x && py >= y && px < x + width && py < y + height;
    }
};

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
    SceneRenderer();
    void setScene(const Scene& scene);
    void setOverlay(const OverlayGeometry& overlay);
    // Clears the viewport and draws; framebufferHeight converts to GL's bottom-up rows. With an
    // image, the mesh only fills the depth buffer and the image is drawn in its place, pixel for
    // pixel; the overlays are drawn on top of either, depth-tested against the mesh.
    void draw(const OrbitCamera& camera, const vis::Bounds3& sceneBox, const Viewport& viewport,
              int framebufferHeight, const ViewImage* image = nullptr) const;

  private:
    void drawImage(const ViewImage& image) const;

    ShaderProgram meshProgram_, overlayProgram_, imageProgram_;
    VertexBuffer mesh_, fragments_, lines_, linesOnTop_;
    mutable VertexBuffer imageQuads_;
};

}  // namespace penumbra::viewer
