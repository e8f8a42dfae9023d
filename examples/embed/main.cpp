// Renders a glTF scene to an image with relief used as a library: embed SCENE.gltf OUT.png
#include <cstdio>

#include "render/renderer.h"
#include "render/validate.h"
#include "scene/image_io.h"

int main(int argc, char** argv) {
  if (argc != 3) return std::fprintf(stderr, "usage: embed SCENE.gltf OUT.png\n"), 2;
  relief::Result<relief::Scene> scene = relief::load_scene(argv[1]);
  if (!scene.ok()) return std::fprintf(stderr, "%s\n", scene.status().message().c_str()), 1;
  relief::Renderer renderer(relief::make_cpu_backend());  // all cores
  relief::RenderOptions options;                          // 800x600, the scene's own techniques
  relief::Result<relief::Frame> frame = renderer.render(*scene, options);
  if (!frame.ok()) return std::fprintf(stderr, "%s\n", frame.status().message().c_str()), 1;
  const relief::RenderResult& result = frame->result;
  relief::Status written = relief::write_image(argv[2], result.framebuffer.color);
  if (!written.ok()) return std::fprintf(stderr, "%s\n", written.message().c_str()), 1;
  std::printf("%s: %dx%d in %.1f ms\n", argv[2], options.width, options.height, result.frame_ms);
  return 0;
}
