// What `rse-ground serve` makes of a request target before it answers
// (docs/mission_control.md): the path and query percent-decoded, a static
// file's place under --web (".." refused), and the content type of a file.
// Pure functions: no sockets, no file reads.
#pragma once

#include <map>
#include <optional>
#include <string>

namespace rse::ground::mission_control {

struct RequestTarget {
    std::string path;                          // decoded, starts with '/'
    std::map<std::string, std::string> query;  // decoded names and values
};

// "/api/history?packet=HK&start=1" -> path and query. nullopt (why in *error)
// for a target that is not an absolute path, a bad %-escape, a NUL, or a
// query parameter given twice.
std::optional<RequestTarget> parseTarget(const std::string& target, std::string* error);

// "%41+b" -> "A+b" (plusIsSpace: "A b", as in a query). nullopt on a bad escape.
std::optional<std::string> percentDecode(const std::string& text, bool plusIsSpace);

// The file a decoded path names under webRoot: "/" is index.html, "/openmct/F"
// is node_modules/openmct/dist/F (the npm package), anything else the file of
// that path. nullopt (why in *error) for a path with a ".." segment, a
// backslash or an empty segment ("//"): refused, never looked up.
std::optional<std::string> staticFilePath(const std::string& webRoot, const std::string& path, std::string* error);

// The Content-Type of a file by its extension (html, js, mjs, css, json, svg,
// png, ico, woff, woff2, map, txt); application/octet-stream otherwise.
const char* contentType(const std::string& file);

}  // namespace rse::ground::mission_control
