#pragma once
// Opening a file a user named. A folder opens as a stream on Linux and reads as empty: a points
// file or an OBJ that is a folder gave no rows or an empty object, silently. Throws InputError
// naming the path unless it is a regular file that opens.

#include <fstream>
#include <string>

namespace penumbra {

// `what` names the kind of file for the message ("points file", "OBJ file").
std::ifstream openInputFile(const std::string& path, const std::string& what,
                            std::ios::openmode mode = std::ios::in);

}  // namespace penumbra
