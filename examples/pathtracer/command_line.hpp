// What the example programs share on the command line: one-line errors with status 2, and
// CLI11 parsing that prints the help on --help.
#pragma once

#include <CLI/CLI.hpp>

#include <cstdlib>
#include <iostream>
#include <string>

namespace pt {

/// Prints "PROGRAM: error: MESSAGE" on one line of stderr and exits with status 2.
[[noreturn]] inline void fail(const char* program, const std::string& message) {
    std::cerr << program << ": error: " << message << "\n";
    std::exit(2);
}

/// Parses the command line into `app`'s options: on --help prints the help and exits 0; on a
/// parse error fails with CLI11's message.
inline void parse_command_line(CLI::App& app, int argc, char** argv, const char* program) {
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp&) {
        std::cout << app.help();
        std::exit(0);
    } catch (const CLI::ParseError& e) {
        fail(program, std::string(e.what()) + " (see --help)");
    }
}

} // namespace pt
