#pragma once
// Opens libadugs_media.so (data/media/media_module.h) the first time a video, a V4L2 webcam or
// an image file in a format other than PNG/JPEG is used. Looked for at $ADUGS_MEDIA_MODULE (a
// path; when set, the only place looked at), next to the running executable (the build puts it
// beside app/adugs), then where this build wrote it (for the test executables).
#include <string>

#include "data/media/media_module.h"

namespace adugs::data {

// The module's functions; data::InputError naming `path` (and `field`) when the module cannot
// be found or opened, with the loader's reason: "<needed_for> need libadugs_media.so: ...".
const MediaFunctions& requireMediaModule(const std::string& path, const std::string& field,
                                         const std::string& needed_for);

// Where the module would be opened from ("" when nowhere), without opening it.
std::string mediaModulePath();

}  // namespace adugs::data
