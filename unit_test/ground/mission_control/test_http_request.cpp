// Request targets (ground/mission_control/http_request.hpp): decoding, the
// static file a path names under --web (".." refused however it is spelled)
// and content types.
#include <string>

#include "ground/mission_control/http_request.hpp"

#include "CppUTest/TestHarness.h"

using rse::ground::mission_control::contentType;
using rse::ground::mission_control::parseTarget;
using rse::ground::mission_control::percentDecode;
using rse::ground::mission_control::staticFilePath;

namespace {

// The file of a target as the server resolves it ("" refused, why in *why).
std::string fileOf(const std::string& target, std::string* why = nullptr) {
    std::string error;
    const auto parsed = parseTarget(target, &error);
    if (!parsed) {
        if (why != nullptr) {
            *why = error;
        }
        return "";
    }
    const auto file = staticFilePath("/web", parsed->path, &error);
    if (why != nullptr) {
        *why = error;
    }
    return file.value_or("");
}

}  // namespace

TEST_GROUP(HttpRequest){};

TEST(HttpRequest, TargetsDecode) {
    std::string error;
    const auto t = parseTarget("/api/history?packet=ROVER_STATE&start=1700000000000&end=1.7e12&x=a%20b+c", &error);
    CHECK_TRUE(t.has_value());
    STRCMP_EQUAL("/api/history", t->path.c_str());
    STRCMP_EQUAL("ROVER_STATE", t->query.at("packet").c_str());
    STRCMP_EQUAL("1700000000000", t->query.at("start").c_str());
    STRCMP_EQUAL("1.7e12", t->query.at("end").c_str());
    STRCMP_EQUAL("a b c", t->query.at("x").c_str());
    CHECK_EQUAL(4U, t->query.size());
    STRCMP_EQUAL("/a b", parseTarget("/a%20b", &error)->path.c_str());
    CHECK_EQUAL(0U, parseTarget("/x?", &error)->query.size());
    STRCMP_EQUAL("", parseTarget("/x?flag", &error)->query.at("flag").c_str());

    CHECK_FALSE(parseTarget("/api/history?packet=HK&packet=PLAN", &error));
    STRCMP_CONTAINS("given twice", error.c_str());
    CHECK_FALSE(parseTarget("/bad%2", &error));
    CHECK_FALSE(parseTarget("/bad%zz", &error));
    CHECK_FALSE(parseTarget("/nul%00", &error));
    CHECK_FALSE(parseTarget("http://host/x", &error));
    CHECK_FALSE(parseTarget("*", &error));
    STRCMP_EQUAL("a+b", percentDecode("a+b", false)->c_str());
    STRCMP_EQUAL("a b", percentDecode("a+b", true)->c_str());
    STRCMP_EQUAL("AZ", percentDecode("%41%5a", false)->c_str());
}

TEST(HttpRequest, StaticFilesUnderTheWebFolder) {
    STRCMP_EQUAL("/web/index.html", fileOf("/").c_str());
    STRCMP_EQUAL("/web/index.html", fileOf("/index.html").c_str());
    STRCMP_EQUAL("/web/views/map.js", fileOf("/views/map.js?v=3").c_str());
    STRCMP_EQUAL("/web/node_modules/openmct/dist/openmct.js", fileOf("/openmct/openmct.js").c_str());
    STRCMP_EQUAL("/web/node_modules/openmct/dist/fonts/x.woff2", fileOf("/openmct/fonts/x.woff2").c_str());
    STRCMP_EQUAL("/web/..data", fileOf("/..data").c_str());  // a name starting with dots is a name
}

TEST(HttpRequest, DotDotIsRefusedHoweverSpelled) {
    std::string why;
    for (const char* target : {"/..", "/../etc/passwd", "/a/../../etc/passwd", "/%2e%2e/etc/passwd", "/%2E%2e/x",
                               "/openmct/../../secret", "/a/..", "/a/%2e%2e/b", "/a\\..\\b", "/a%5c..%5cb", "/./x",
                               "//etc/passwd"}) {
        CHECK_TEXT(fileOf(target, &why).empty(), target);
        CHECK_TEXT(!why.empty(), target);
    }
    fileOf("/../etc/passwd", &why);
    STRCMP_CONTAINS("'..'", why.c_str());
}

TEST(HttpRequest, ContentTypes) {
    STRCMP_EQUAL("text/html; charset=utf-8", contentType("/web/index.html"));
    STRCMP_EQUAL("text/javascript; charset=utf-8", contentType("/web/rse-plugin.js"));
    STRCMP_EQUAL("text/css; charset=utf-8", contentType("/web/a.CSS"));
    STRCMP_EQUAL("application/json", contentType("/web/package.json"));
    STRCMP_EQUAL("application/json", contentType("/web/openmct.js.map"));
    STRCMP_EQUAL("image/svg+xml", contentType("/web/icon.svg"));
    STRCMP_EQUAL("image/png", contentType("/web/rover.png"));
    STRCMP_EQUAL("font/woff", contentType("/web/f.woff"));
    STRCMP_EQUAL("font/woff2", contentType("/web/f.woff2"));
    STRCMP_EQUAL("application/octet-stream", contentType("/web/data.bin"));
    STRCMP_EQUAL("application/octet-stream", contentType("/web.d/README"));
}
