// The image files a model names, found as the tools that wrote them meant (SPEC 3.2).
#pragma once

#include <filesystem>
#include <string>

namespace mbao {

// The file that `reference`, an image path as a model file gives it, names
// for a model in `model_folder`: `\` read as `/`, a leading `//` (Blender's
// "relative to the .blend") dropped, then the path relative to the model's
// folder (or as it is, where absolute); where that is no file, or the path is
// a Windows one (a drive letter), its file name alone in the model's folder.
// Where none exists, the first place tried, for the message that says so.
std::filesystem::path find_texture_file(const std::filesystem::path& model_folder, const std::string& reference);

// Whether an image of this file name cannot hold an alpha channel (JPEG), so
// that it need not be opened to learn that it cuts no surface.
bool cannot_hold_alpha(const std::string& reference);

}  // namespace mbao
