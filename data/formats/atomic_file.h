#pragma once
// Write-then-rename: readers (and a killed run) never see a half-written output file.
#include <string>

namespace adugs::data {

// Writes content to path + ".tmp", then renames it over path. Throws InputError naming path.
void writeTextFileAtomically(const std::string& path, const std::string& content);

}  // namespace adugs::data
