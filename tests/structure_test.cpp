// The project's structure, checked on its sources: the library's folders layer without an
// include cycle, no function of the examples (what integrators copy) is longer than 60 lines,
// the library's comments quote no timings, and concepts.hpp indexes every concept.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

const fs::path source_dir = RESTIR_SOURCE_DIR;
constexpr int max_function_lines = 60;

std::string read_text(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

using Graph = std::map<std::string, std::set<std::string>>;

/// The folder of a header below include/restir ("reuse" for restir/reuse/x.hpp); a header at
/// the top level is a node of its own ("concepts.hpp").
std::string node_of(const std::string& header) {
    const std::string path = header.substr(header.find('/') + 1);
    const std::size_t slash = path.find('/');
    return slash == std::string::npos ? path : path.substr(0, slash);
}

/// Edges between the nodes of `#include "restir/..."` lines of every library header.
Graph library_include_graph() {
    Graph graph;
    const std::regex include_line(R"re(#include\s+"(restir/[^"]+)")re");
    for (const auto& entry : fs::recursive_directory_iterator(source_dir / "include")) {
        if (entry.path().extension() != ".hpp")
            continue;
        const std::string header = fs::relative(entry.path(), source_dir / "include").string();
        const std::string from = node_of(header);
        graph[from];
        const std::string text = read_text(entry.path());
        for (std::sregex_iterator it(text.begin(), text.end(), include_line), end; it != end;
             ++it) {
            const std::string to = node_of((*it)[1].str());
            if (to != from)
                graph[from].insert(to);
        }
    }
    return graph;
}

/// One cycle of `graph` as "a -> b -> a", or "" when it has none (depth-first search).
std::string find_cycle(const Graph& graph) {
    std::map<std::string, int> state; // 0 unvisited, 1 on the path, 2 done
    std::vector<std::string> path;
    std::string cycle;
    auto visit = [&](auto&& self, const std::string& node) -> bool {
        state[node] = 1;
        path.push_back(node);
        const auto edges = graph.find(node);
        if (edges != graph.end())
            for (const std::string& next : edges->second) {
                if (state[next] == 1) {
                    auto from = std::find(path.begin(), path.end(), next);
                    for (; from != path.end(); ++from)
                        cycle += *from + " -> ";
                    cycle += next;
                    return true;
                }
                if (state[next] == 0 && self(self, next))
                    return true;
            }
        path.pop_back();
        state[node] = 2;
        return false;
    };
    for (const auto& [node, edges] : graph)
        if (state[node] == 0 && visit(visit, node))
            return cycle;
    return "";
}

/// `text` with comments, preprocessor lines, string and character literals blanked, line
/// breaks kept.
std::string code_only(const std::string& text) {
    std::string out = text;
    for (std::size_t i = 0; i < out.size(); ++i) {
        // Blanks [i, end) (to the end of the text when `end` is npos); i ends on the last
        // blanked character, so the loop goes on after it.
        auto blank_until = [&](std::size_t end) {
            const std::size_t first = i;
            for (; i < std::min(end, out.size()); ++i)
                if (out[i] != '\n')
                    out[i] = ' ';
            i = std::max(i, first + 1) - 1;
        };
        // Past the closing `token` found after the `opening` characters at i, or npos when the
        // text ends first.
        auto past = [&](const char* token, std::size_t opening) {
            const std::size_t at = out.find(token, i + opening);
            return at == std::string::npos ? at : at + std::char_traits<char>::length(token);
        };
        const std::size_t line_start = out.rfind('\n', i) + 1; // 0 on the first line
        const bool line_begins_here = out.find_first_not_of(" \t", line_start) == i;
        if (out[i] == '#' && line_begins_here) {
            blank_until(out.find('\n', i));
        } else if (out.compare(i, 2, "//") == 0) {
            blank_until(out.find('\n', i));
        } else if (out.compare(i, 2, "/*") == 0) {
            blank_until(past("*/", 2));
        } else if (out.compare(i, 3, "R\"(") == 0) {
            blank_until(past(")\"", 3));
        } else if (out[i] == '"' ||
                   (out[i] == '\'' &&
                    (i == 0 || !std::isalnum(static_cast<unsigned char>(out[i - 1]))))) {
            const char quote = out[i];
            std::size_t end = i + 1;
            while (end < out.size() && out[end] != quote && out[end] != '\n')
                end += out[end] == '\\' ? 2 : 1;
            blank_until(end + 1);
        }
    }
    return out;
}

struct LongFunction {
    int first_line = 0;
    int lines = 0;
};

/// Functions (and lambdas at namespace or class scope) of `text` whose body, from the line of
/// its opening brace to the line of its closing brace, is longer than `limit` lines. A brace
/// opens a function body when only namespaces and classes enclose it and the text before it,
/// since the previous `;`, `{` or `}`, has a parenthesis and is no namespace, class or enum.
std::vector<LongFunction> long_functions(const std::string& text, int limit) {
    const std::string code = code_only(text);
    struct Open {
        bool scope = false;    ///< A namespace, class, struct, union or enum.
        bool function = false; ///< A function body at namespace or class scope.
        int line = 0;
    };
    std::vector<Open> open;
    std::vector<LongFunction> found;
    const std::regex scope_head(
        R"(^\s*(template\s*<[^{]*>\s*)?(namespace|class|struct|union|enum|extern)\b)");
    std::size_t head_start = 0;
    int line = 1;
    for (std::size_t i = 0; i < code.size(); ++i) {
        const char c = code[i];
        if (c == '\n')
            ++line;
        if (c == '{') {
            const std::string head = code.substr(head_start, i - head_start);
            const bool at_scope =
                std::all_of(open.begin(), open.end(), [](const Open& o) { return o.scope; });
            const bool scope =
                std::regex_search(head, scope_head) && head.find('(') == std::string::npos;
            open.push_back(
                {scope, at_scope && !scope && head.find('(') != std::string::npos, line});
            head_start = i + 1;
        } else if (c == '}' && !open.empty()) {
            const Open block = open.back();
            open.pop_back();
            if (block.function && line - block.line + 1 > limit)
                found.push_back({block.line, line - block.line + 1});
            head_start = i + 1;
        } else if (c == ';') {
            head_start = i + 1;
        }
    }
    return found;
}

TEST(Structure, FindsACycleOnlyWhereThereIsOne) {
    EXPECT_EQ(find_cycle({{"a", {"b"}}, {"b", {"c"}}, {"c", {}}}), "");
    EXPECT_EQ(find_cycle({{"a", {"b"}}, {"b", {"c"}}, {"c", {"b"}}}), "b -> c -> b");
    EXPECT_EQ(node_of("restir/reuse/spatial.hpp"), "reuse");
    EXPECT_EQ(node_of("restir/concepts.hpp"), "concepts.hpp");
}

TEST(Structure, LibraryFoldersIncludeEachOtherWithoutACycle) {
    const Graph graph = library_include_graph();
    ASSERT_GE(graph.size(), 5u) << "include/restir not found under " << source_dir;
    EXPECT_EQ(find_cycle(graph), "") << "an include cycle between folders of include/restir";
    // The bridge pulls in no host-only code: the concepts need only the core.
    for (const std::string& to : graph.at("concepts.hpp"))
        EXPECT_TRUE(to == "core" || to == "config.hpp") << "concepts.hpp includes " << to;
}

TEST(Structure, MeasuresFunctionLengths) {
    const std::string source = "namespace n {\n"
                               "struct S {\n"
                               "    int f() {\n"
                               "        if (x) {\n"
                               "        }\n"
                               "        return 1; // }\n"
                               "    }\n"
                               "};\n"
                               "#define F(x) {\n"
                               "const char* s = \"{\";\n"
                               "}\n";
    const std::vector<LongFunction> found = long_functions(source, 4);
    ASSERT_EQ(found.size(), 1u);
    EXPECT_EQ(found[0].first_line, 3);
    EXPECT_EQ(found[0].lines, 5);
    EXPECT_TRUE(long_functions(source, 5).empty());
    // Unterminated comments and literals end at the end of the text.
    EXPECT_TRUE(long_functions("int f() {\n/* never closed", 1).empty());
    EXPECT_TRUE(long_functions("const char* s = R\"(never closed", 1).empty());
}

TEST(Structure, ExampleFunctionsAreShort) {
    int files = 0;
    for (const auto& entry : fs::recursive_directory_iterator(source_dir / "examples")) {
        const std::string extension = entry.path().extension().string();
        if (extension != ".cpp" && extension != ".hpp")
            continue;
        ++files;
        for (const LongFunction& f : long_functions(read_text(entry.path()), max_function_lines))
            ADD_FAILURE() << fs::relative(entry.path(), source_dir).string() << ":" << f.first_line
                          << ": a function of " << f.lines << " lines (at most "
                          << max_function_lines << ")";
    }
    EXPECT_GT(files, 10);
}

/// The `// ` and `/// ` comments of `text`, one string per line.
std::vector<std::string> comment_lines(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
        const std::size_t at = line.find("//");
        if (at != std::string::npos)
            lines.push_back(line.substr(at));
    }
    return lines;
}

/// Whether a comment quotes a timing or a speed-up, which belong in docs/performance.md.
bool quotes_a_timing(const std::string& comment) {
    static const std::regex timing(
        R"re([0-9] ?(ns|us|ms)\b|[0-9.]+ ?x (faster|slower)|[0-9] ?% (faster|slower))re");
    return std::regex_search(comment, timing);
}

TEST(Structure, FindsTimingsInComments) {
    EXPECT_TRUE(quotes_a_timing("// took 8.4 ms against 6.6"));
    EXPECT_TRUE(quotes_a_timing("/// 4x slower draws"));
    EXPECT_TRUE(quotes_a_timing("// 10-20 % slower with g++ 12"));
    EXPECT_TRUE(quotes_a_timing("// 25 ns a draw"));
    EXPECT_FALSE(quotes_a_timing("// 1e-9 sr, 1 % more for rounding"));
    EXPECT_FALSE(quotes_a_timing("/// converges faster (docs/performance.md)"));
    EXPECT_EQ(comment_lines("int x; // a\nint y;\n/// b\n").size(), 2u);
}

// Figures go stale: the library's comments say why, docs/performance.md says how fast.
TEST(Structure, LibraryCommentsQuoteNoTimings) {
    for (const auto& entry : fs::recursive_directory_iterator(source_dir / "include")) {
        if (entry.path().extension() != ".hpp")
            continue;
        for (const std::string& comment : comment_lines(read_text(entry.path()))) {
            EXPECT_FALSE(quotes_a_timing(comment))
                << fs::relative(entry.path(), source_dir).string() << ": " << comment;
        }
    }
}

// concepts.hpp indexes every concept of the library: each is defined there or named in its
// list of the concepts that live beside their stages.
TEST(Structure, ConceptsHppIndexesEveryConcept) {
    const std::string index = read_text(source_dir / "include/restir/concepts.hpp");
    const std::regex definition(R"re(\bconcept\s+([A-Za-z_][A-Za-z0-9_]*)\s*=)re");
    int concepts = 0;
    for (const auto& entry : fs::recursive_directory_iterator(source_dir / "include")) {
        if (entry.path().extension() != ".hpp")
            continue;
        const std::string text = read_text(entry.path());
        for (std::sregex_iterator it(text.begin(), text.end(), definition), end; it != end; ++it) {
            ++concepts;
            const std::regex named("(//   |concept )" + (*it)[1].str() + "\\b");
            EXPECT_TRUE(std::regex_search(index, named))
                << (*it)[1].str() << " (" << fs::relative(entry.path(), source_dir).string()
                << ") is not in concepts.hpp's index";
        }
    }
    EXPECT_GT(concepts, 20);
}

} // namespace
