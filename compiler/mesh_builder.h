// compiler/mesh_builder.h — trianglemesh and plymesh shapes to TriangleMesh.
//
// Takes the bulk arrays of a "trianglemesh" straight from the directive's
// ParamList (they are not copied into the Entity first) or reads a "plymesh"
// file with the project's one PLY reader (or, for a name ending in .drc in
// any case, its one Draco decoder, format/draco_codec.h), and checks them as
// pbrt-v3 would need them: indices a multiple of 3 and below the vertex count,
// per-vertex arrays of the vertex count, per-face arrays of the triangle count. Errors
// are reported at the offending parameter; the function returns false.
#pragma once

#include "compiler/diagnostics.h"
#include "compiler/params.h"
#include "compiler/scene_desc.h"

namespace pbrtc {

bool build_trianglemesh(const ParamList& params, Loc shape_loc, Diagnostics* diag,
                        TriangleMesh* mesh);
bool load_plymesh(const std::string& path, Loc filename_loc, Diagnostics* diag, TriangleMesh* mesh);

}  // namespace pbrtc
