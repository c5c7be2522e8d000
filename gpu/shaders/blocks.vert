#version 330 core
// The vertices of a pass drawn over the runs of a block map (GpuScene::draw with a block cover):
// one point per row of the map and segment of kBlockSegment blocks along it, which blocks.geom
// turns into the rectangles of that segment's runs. The map never leaves the GPU.
uniform int segments;  // segments per row of the map
flat out ivec2 segmentRow;
void main() {
  segmentRow = ivec2(gl_VertexID % segments, gl_VertexID / segments);
  gl_Position = vec4(0.0, 0.0, 0.0, 1.0);
}
