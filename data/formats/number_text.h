#pragma once
// Numbers as the project's writers print them: the shortest text that parses back to exactly the
// same double (std::to_chars), so a file written and read again holds the same values.
#include <string>
#include <vector>

namespace adugs::data {

std::string shortestText(double value);
// "[a, b, c]"
std::string listText(const std::vector<double>& values);

}  // namespace adugs::data
