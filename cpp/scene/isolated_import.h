// Runs a third-party importer where its crashes cannot reach the caller:
// Debian's Assimp aborts on some malformed files (its ai_assert stays on) and
// may crash on others, which in the process would take Python down with it.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "scene/alpha_masks.h"
#include "scene/camera.h"
#include "scene/triangle_mesh.h"
#include "scene/uv_sets.h"

namespace mbao {

// What a loader hands to Scene's constructor.
struct ImportedScene {
  TriangleMesh mesh;
  AlphaMasks masks;
  std::optional<Camera> camera;
  std::vector<std::string> warnings;
  UvSets uv_sets;  // loaded where asked for
};

// import() run in a child process (fork), its result sent back through a pipe.
// Its LoadError is rethrown here; a child that dies (a signal, an abort), or
// runs past `seconds` (some malformed files loop the importer forever), is a
// LoadError naming `path`. import() must touch nothing but the file and its
// own memory: the child runs it beside none of the parent's other threads.
ImportedScene import_isolated(const std::function<ImportedScene()>& import, const std::string& path, double seconds);

}  // namespace mbao
