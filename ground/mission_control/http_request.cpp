#include "ground/mission_control/http_request.hpp"

#include "ground/text_format.hpp"

namespace rse::ground::mission_control {

std::optional<std::string> percentDecode(const std::string& text, bool plusIsSpace) {
    std::string out;
    out.reserve(text.size());
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (c == '%') {
            if (i + 2 >= text.size()) {
                return std::nullopt;
            }
            const int high = hexDigit(text[i + 1]);
            const int low = hexDigit(text[i + 2]);
            if (high < 0 || low < 0) {
                return std::nullopt;
            }
            out += static_cast<char>(high * 16 + low);
            i += 2;
        } else if (c == '+' && plusIsSpace) {
            out += ' ';
        } else {
            out += c;
        }
    }
    return out;
}

std::optional<RequestTarget> parseTarget(const std::string& target, std::string* error) {
    const std::size_t mark = target.find('?');
    const std::string rawPath = target.substr(0, mark);
    RequestTarget result;
    std::optional<std::string> path = percentDecode(rawPath, false);
    if (!path) {
        *error = "bad %-escape in the path";
        return std::nullopt;
    }
    if (path->empty() || (*path)[0] != '/') {
        *error = "the path must start with /";
        return std::nullopt;
    }
    if (path->find('\0') != std::string::npos) {
        *error = "NUL in the path";
        return std::nullopt;
    }
    result.path = *path;
    if (mark == std::string::npos) {
        return result;
    }
    const std::string query = target.substr(mark + 1);
    std::size_t start = 0;
    while (start <= query.size()) {
        std::size_t end = query.find('&', start);
        if (end == std::string::npos) {
            end = query.size();
        }
        const std::string pair = query.substr(start, end - start);
        start = end + 1;
        if (pair.empty()) {
            continue;
        }
        const std::size_t equals = pair.find('=');
        std::optional<std::string> name = percentDecode(pair.substr(0, equals), true);
        std::optional<std::string> value =
            percentDecode(equals == std::string::npos ? std::string() : pair.substr(equals + 1), true);
        if (!name || !value) {
            *error = "bad %-escape in the query";
            return std::nullopt;
        }
        if (!result.query.emplace(*name, *value).second) {
            *error = "query parameter '" + *name + "' given twice";
            return std::nullopt;
        }
    }
    return result;
}

std::optional<std::string> staticFilePath(const std::string& webRoot, const std::string& path, std::string* error) {
    if (path.empty() || path[0] != '/') {
        *error = "the path must start with /";
        return std::nullopt;
    }
    if (path.find('\\') != std::string::npos || path.find('\0') != std::string::npos) {
        *error = "backslash or NUL in the path";
        return std::nullopt;
    }
    // Every segment between slashes: none may be "..", "." or empty (but the
    // path may end in a slash only as "/").
    std::size_t start = 1;
    while (start <= path.size() && path != "/") {
        std::size_t end = path.find('/', start);
        if (end == std::string::npos) {
            end = path.size();
        }
        const std::string segment = path.substr(start, end - start);
        if (segment == "..") {
            *error = "'..' in the path";
            return std::nullopt;
        }
        if (segment.empty() || segment == ".") {
            *error = "empty or '.' segment in the path";
            return std::nullopt;
        }
        start = end + 1;
    }
    if (path == "/") {
        return webRoot + "/index.html";
    }
    const std::string openmct = "/openmct/";
    if (path.compare(0, openmct.size(), openmct) == 0) {
        return webRoot + "/node_modules/openmct/dist/" + path.substr(openmct.size());
    }
    return webRoot + path;
}

const char* contentType(const std::string& file) {
    struct Type {
        const char* extension;
        const char* type;
    };
    static const Type kTypes[] = {
        {".html", "text/html; charset=utf-8"},
        {".js", "text/javascript; charset=utf-8"},
        {".mjs", "text/javascript; charset=utf-8"},
        {".css", "text/css; charset=utf-8"},
        {".json", "application/json"},
        {".map", "application/json"},
        {".svg", "image/svg+xml"},
        {".png", "image/png"},
        {".ico", "image/x-icon"},
        {".woff", "font/woff"},
        {".woff2", "font/woff2"},
        {".txt", "text/plain; charset=utf-8"},
    };
    const std::size_t dot = file.rfind('.');
    const std::size_t slash = file.rfind('/');
    if (dot != std::string::npos && (slash == std::string::npos || dot > slash)) {
        const std::string extension = toLower(file.substr(dot));
        for (const Type& t : kTypes) {
            if (extension == t.extension) {
                return t.type;
            }
        }
    }
    return "application/octet-stream";
}

}  // namespace rse::ground::mission_control
