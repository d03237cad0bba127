// Exports the command and telemetry dictionary (fsw/cmdtlm/dictionary.def, as
// expanded into the flight's descriptors) as a readable Markdown document and as
// a machine-readable JSON file: docs/dictionary.md and docs/dictionary.json are
// these functions' output (`rse-ground dict --markdown|--json`), and a unit test
// fails when the files in docs/ differ from what they return now.
#pragma once

#include <string>

namespace rse::ground {

std::string exportDictionaryMarkdown();
std::string exportDictionaryJson();

// The meaning of each CMD_ACK reason code (0 = accepted), for the documents and
// for rse-ground's messages; "" for an unknown code.
const char* rejectReasonDescription(unsigned reason);

}  // namespace rse::ground
