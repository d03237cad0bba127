// The console text of a lockstep mission: sim::runMission writes its console
// to a FILE; this is one in memory, read back as a string. Shared by the
// lockstep tests that assert on a mission's events and POINT lines.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <string>

namespace rse::test {

struct MissionConsole {
    char* text = nullptr;
    std::size_t size = 0;
    std::FILE* file = open_memstream(&text, &size);

    MissionConsole() = default;
    MissionConsole(const MissionConsole&) = delete;
    MissionConsole& operator=(const MissionConsole&) = delete;
    ~MissionConsole() {
        if (file != nullptr) {
            std::fclose(file);
        }
        std::free(text);
    }
    std::string str() {
        std::fflush(file);
        return std::string(text, size);
    }
};

}  // namespace rse::test
