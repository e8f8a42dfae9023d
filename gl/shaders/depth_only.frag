#version 450 core
// Shadow-pass casters without a shadow-pass variant (render/cpu_backend.cpp depth_only): the
// polygon's own depth, nothing shaded, nothing counted.
void main() {}
