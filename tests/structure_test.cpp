// The project's structure, checked on its sources: the library's folders layer without an
// include cycle, no function of the library or the examples (what integrators copy) is longer
// than 60 lines and no file longer than 500, the library's comments quote no timings, and
// concepts.hpp indexes every concept.
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
constexpr int max_file_lines = 500;

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

/// A function longer than the limit: the line of its opening brace, its length from that line
/// to the line of its closing brace, and its name, qualified by the classes around it.
struct LongFunction {
    int first_line = 0;
    int lines = 0;
    std::string name;
};

/// `head` with each character inside parentheses, brackets, braces or template arguments
/// blanked (those at depth 0 kept, the brackets themselves too). A `<` counts as an opening
/// angle bracket outside parentheses only, and not after `operator` or before `=`.
std::string outermost(const std::string& head) {
    static const std::regex after_operator(R"(\boperator\s*<*$)");
    std::string out = head;
    int parens = 0, angles = 0;
    for (std::size_t i = 0; i < head.size(); ++i) {
        const char c = head[i];
        const bool inside = parens > 0 || angles > 0;
        if (c == '(' || c == '[' || c == '{') {
            ++parens;
        } else if ((c == ')' || c == ']' || c == '}') && parens > 0) {
            --parens;
        } else if (c == '<' && parens == 0 && head.compare(i + 1, 1, "=") != 0 &&
                   !std::regex_search(head.substr(0, i), after_operator)) {
            ++angles;
        } else if (c == '>' && parens == 0 && angles > 0 && (i == 0 || head[i - 1] != '-')) {
            --angles;
        }
        if (inside && (parens > 0 || angles > 0))
            out[i] = ' ';
    }
    return out;
}

/// `head` without its leading `template <...>` parameter lists and attributes (`[[...]]`,
/// `alignas(...)`, `__attribute__((...))`), each blanked.
std::string without_templates_and_attributes(const std::string& head) {
    std::string out = head;
    const std::string depth0 = outermost(head);
    static const std::regex opening(R"(\btemplate\s*<|\[\[|\balignas\s*\(|\b__attribute__\s*\()");
    for (std::sregex_iterator it(head.begin(), head.end(), opening), end; it != end; ++it) {
        const std::size_t from = static_cast<std::size_t>(it->position());
        if (depth0[from] != head[from])
            continue; // inside brackets
        // The opening bracket's match: the next bracket of its kind at depth 0.
        const char closing = it->str().back() == '<' ? '>' : it->str().back() == '[' ? ']' : ')';
        const std::size_t to = depth0.find(closing, from + static_cast<std::size_t>(it->length()));
        std::fill(out.begin() + static_cast<std::ptrdiff_t>(from),
                  to == std::string::npos ? out.end()
                                          : out.begin() + static_cast<std::ptrdiff_t>(to + 1),
                  ' ');
    }
    return out;
}

/// What a brace opens, from the code before it (since the previous `;`, `{` or `}`).
enum class Opens { scope, function, other };

/// Whether the brace after `head` opens a namespace, class, struct, union or enum (whatever
/// macros without parentheses or templates come first), a function or lambda body (a
/// parenthesis in the head, or a lambda's `[...]` at its end), or something else.
Opens what_opens(const std::string& head, std::string& scope_name) {
    const std::string bare = outermost(without_templates_and_attributes(head));
    static const std::regex scope_keyword(
        R"(\b(namespace|class|struct|union|enum|extern)\b\s*([A-Za-z_]\w*)?)");
    std::smatch keyword;
    if (std::regex_search(bare, keyword, scope_keyword) &&
        keyword.suffix().str().find('(') == std::string::npos) {
        scope_name = keyword[1] == "namespace" || keyword[1] == "extern" ? "" : keyword[2].str();
        return Opens::scope;
    }
    static const std::regex concept_head(R"(\bconcept\b)");
    static const std::regex lambda_without_parameters(
        R"((^|[=(,{]|\breturn)\s*\[[^\]]*\]\s*(mutable\s*)?$)");
    if (std::regex_search(head, concept_head))
        return Opens::other;
    if (head.find('(') != std::string::npos || std::regex_search(head, lambda_without_parameters))
        return Opens::function;
    return Opens::other;
}

/// The name of the function or lambda whose head (the code before its body's brace) is
/// `head`: the name before the parameters (`S::f`, `operator()`), or for a lambda the
/// variable it initialises.
std::string function_name(const std::string& head) {
    const std::string bare = without_templates_and_attributes(head);
    static const std::regex lambda(R"(^[^(]*?\b([A-Za-z_]\w*)\s*=\s*\[)");
    static const std::regex op(
        R"(((?:[A-Za-z_]\w*\s*::\s*)*)\boperator\b\s*(\(\s*\)|\[\s*\]|[^(]*?)\s*\()");
    static const std::regex named(R"(((?:[A-Za-z_]\w*\s*::\s*)*~?([A-Za-z_]\w*))\s*\()");
    static const std::set<std::string> not_names = {
        "requires",      "alignas",  "decltype", "noexcept", "sizeof", "alignof", "__attribute__",
        "static_assert", "explicit", "if",       "while",    "for",    "switch",  "return"};
    const std::string depth0 = outermost(bare);
    const auto no_spaces = [](std::string text) {
        text.erase(
            std::remove_if(text.begin(), text.end(),
                           [](char c) { return std::isspace(static_cast<unsigned char>(c)); }),
            text.end());
        return text;
    };
    std::smatch match;
    if (std::regex_search(bare, match, lambda))
        return match[1].str();
    if (std::regex_search(depth0, match, op)) {
        const std::string symbol = no_spaces(match[2].str());
        const bool conversion =
            !symbol.empty() && std::isalpha(static_cast<unsigned char>(symbol[0]));
        return no_spaces(match[1].str()) + "operator" + (conversion ? " " : "") + symbol;
    }
    for (std::sregex_iterator it(depth0.begin(), depth0.end(), named), end; it != end; ++it)
        if (!not_names.contains((*it)[2].str()))
            return no_spaces((*it)[1].str());
    return "(unnamed)";
}

/// Whether a brace after `head` belongs to the head of a declaration that goes on after it: a
/// brace inside parentheses (a default argument `= {}`) or a requires-expression (`requires
/// requires(T t) { t.f(); }`, `= requires {`, `&& requires(...) {`).
bool brace_in_head(const std::string& head) {
    static const std::regex requires_expression(
        R"((\brequires|[=!,(&|])\s*\brequires\s*(\((?:[^()]|\([^()]*\))*\))?\s*$)");
    return std::count(head.begin(), head.end(), '(') > std::count(head.begin(), head.end(), ')') ||
           std::regex_search(head, requires_expression);
}

/// Whether `head` ends in a lambda's captures and parameters (`[&](int i) -> float `).
bool ends_in_lambda_declarator(const std::string& head) {
    static const std::regex declarator(
        R"(\]\s*(\((?:[^()]|\([^()]*\))*\))?(\s|\bmutable\b|\bconstexpr\b|\bnoexcept\b)*(->[^{};]*)?$)");
    return std::regex_search(head, declarator);
}

/// Functions (and lambdas at namespace or class scope) of `text` whose body, from the line of
/// its opening brace to the line of its closing brace, is longer than `limit` lines. A brace
/// opens a function body when only namespaces and classes enclose it and `what_opens` says so
/// of the code before it (since the previous `;`, `{` or `}`); a lambda inside a function
/// counts toward that function, and one passed to an initialiser at namespace or class scope
/// is a function of its own. The braces of a default argument, a requires-expression or a
/// constructor's member initialisers (`: a{x}, b{y} {`) belong to the head after them.
std::vector<LongFunction> long_functions(const std::string& text, int limit) {
    const std::string code = code_only(text);
    struct Open {
        Opens kind = Opens::other;
        bool at_scope = false; ///< Only namespaces and classes enclose it.
        bool in_head = false;  ///< Part of the head of the declaration after it.
        int line = 0;
        std::string name;           ///< A class's or function's name ("" for others).
        std::size_t head_start = 0; ///< Where the code before its brace begins.
    };
    std::vector<Open> open;
    std::vector<LongFunction> found;
    static const std::regex member_initialisers(R"(\)\s*(noexcept\s*)?:\s*[A-Za-z_])");
    std::size_t head_start = 0;
    int line = 1;
    for (std::size_t i = 0; i < code.size(); ++i) {
        const char c = code[i];
        if (c == '\n')
            ++line;
        if (c == '{') {
            const std::string head = code.substr(head_start, i - head_start);
            Open block{Opens::other, false, brace_in_head(head), line, "", head_start};
            block.at_scope = std::all_of(open.begin(), open.end(),
                                         [](const Open& o) { return o.kind == Opens::scope; });
            if (!block.in_head)
                block.kind = what_opens(head, block.name);
            else if (ends_in_lambda_declarator(head))
                block.kind = Opens::function; // a lambda argument of an initialiser
            if (block.kind == Opens::function)
                block.name = function_name(head);
            open.push_back(block);
            head_start = i + 1;
        } else if (c == '}' && !open.empty()) {
            const Open block = open.back();
            open.pop_back();
            const std::size_t next = code.find_first_not_of(" \t\n", i + 1);
            const bool initialiser =
                block.kind == Opens::function && next != std::string::npos &&
                (code[next] == ',' || code[next] == '{') &&
                std::regex_search(code.substr(block.head_start, i - block.head_start),
                                  member_initialisers);
            head_start = block.in_head || initialiser ? block.head_start : i + 1;
            if (block.kind != Opens::function || initialiser || !block.at_scope ||
                line - block.line + 1 <= limit)
                continue;
            std::string qualified = block.name;
            for (auto o = open.rbegin(); o != open.rend(); ++o)
                if (!o->name.empty())
                    qualified = o->name + "::" + qualified;
            found.push_back({block.line, line - block.line + 1, qualified});
        } else if (c == ';') {
            head_start = i + 1;
        }
    }
    return found;
}

/// The lines of `text`: its line breaks, and one more where its last line has none.
int line_count(const std::string& text) {
    const auto breaks = static_cast<int>(std::count(text.begin(), text.end(), '\n'));
    return breaks + (text.empty() || text.back() == '\n' ? 0 : 1);
}

/// The C++ sources (.hpp, .cpp, .cu) below `folder` of the source tree, sorted.
std::vector<fs::path> sources_below(const std::string& folder) {
    std::vector<fs::path> sources;
    for (const auto& entry : fs::recursive_directory_iterator(source_dir / folder)) {
        const std::string extension = entry.path().extension().string();
        if (extension == ".hpp" || extension == ".cpp" || extension == ".cu")
            sources.push_back(entry.path());
    }
    std::sort(sources.begin(), sources.end());
    return sources;
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
    EXPECT_EQ(found[0].name, "S::f");
    EXPECT_TRUE(long_functions(source, 5).empty());
    // Unterminated comments and literals end at the end of the text.
    EXPECT_TRUE(long_functions("int f() {\n/* never closed", 1).empty());
    EXPECT_TRUE(long_functions("const char* s = R\"(never closed", 1).empty());
}

// The library's forms: a macro line before a namespace, attributes and `alignas` on a class,
// templates with `requires` clauses and requires-expressions, annotation macros, default
// arguments `= {}`, member functions, constructors with member initialisers, out-of-class
// definitions, operators, and lambdas, which count toward the function around them.
TEST(Structure, MeasuresFunctionLengthsInTheLibrarysStyle) {
    const std::vector<std::string> lines = {
        "RESTIR_VECTORIZE_REGION_BEGIN",                                        // 1
        "namespace restir::detail {",                                           // 2
        "template <class G>",                                                   // 3
        "requires requires(const G& g, int p) { g.surface(p); }",               // 4
        "RESTIR_HOST_DEVICE constexpr auto surface_at(const G& g, int p) {",    // 5
        "    return g.surface(p);",                                             // 6
        "}",                                                                    // 7
        "struct alignas(64) [[nodiscard]] Group : Base<decltype(f(1))> {",      // 8
        "    template <typename F>",                                            // 9
        "        requires(sizeof(F) > 4) && std::invocable<F, int>",            // 10
        "    RESTIR_HOST_DEVICE RESTIR_FORCE_INLINE float bounds(F f) const {", // 11
        "        auto g = [&](int i) {",                                        // 12
        "            return f(i);",                                             // 13
        "        };",                                                           // 14
        "        return g(0);",                                                 // 15
        "    }",                                                                // 16
        "    Group(int x) : a{x}, b(x), c{",                                    // 17
        "        x} {",                                                         // 18
        "        a += 1;",                                                      // 19
        "    }",                                                                // 20
        "    struct Inner {",                                                   // 21
        "        bool operator()(int x) const {",                               // 22
        "            return x > 0;",                                            // 23
        "        }",                                                            // 24
        "    };",                                                               // 25
        "    float table[3] = {1.0f, 2.0f,",                                    // 26
        "                      3.0f};",                                         // 27
        "    float shade(int x, const Options& options = {}) const requires",   // 28
        "        requires(const G& g) { g.surface(0); }",                       // 29
        "    {",                                                                // 30
        "        return 1.0f;",                                                 // 31
        "    }",                                                                // 32
        "};",                                                                   // 33
        "template <typename T>",                                                // 34
        "concept Lit = requires(T t) {",                                        // 35
        "    t.f();",                                                           // 36
        "};",                                                                   // 37
        "inline float View::choose(float u) const noexcept {",                  // 38
        "    return u;",                                                        // 39
        "}",                                                                    // 40
        "inline const auto twice = [](float x) {",                              // 41
        "    return 2.0f * x;",                                                 // 42
        "};",                                                                   // 43
        "const Validator finite(",                                              // 44
        "    [](std::string& text) -> std::string {",                           // 45
        "        return text;",                                                 // 46
        "    },",                                                               // 47
        "    0);",                                                              // 48
        "} // namespace restir::detail",                                        // 49
        "RESTIR_VECTORIZE_REGION_END"};
    std::string source;
    for (const std::string& line : lines)
        source += line + "\n";
    std::vector<std::string> found;
    for (const LongFunction& f : long_functions(source, 2))
        found.push_back(std::to_string(f.first_line) + " " + f.name + " " +
                        std::to_string(f.lines));
    const std::vector<std::string> expected = {"5 surface_at 3",    "11 Group::bounds 6",
                                               "18 Group::Group 3", "22 Group::Inner::operator() 3",
                                               "30 Group::shade 3", "38 View::choose 3",
                                               "41 twice 3",        "45 finite 3"};
    EXPECT_EQ(found, expected);
}

TEST(Structure, CountsFileLines) {
    EXPECT_EQ(line_count(""), 0);
    EXPECT_EQ(line_count("a"), 1);
    EXPECT_EQ(line_count("a\n"), 1);
    EXPECT_EQ(line_count("a\nb"), 2);
    EXPECT_EQ(line_count("a\n\n"), 2);
    EXPECT_EQ(line_count("\n\n\n"), 3);
}

/// Fails once per function of the sources below `folder` longer than `max_function_lines`,
/// naming it with its path and line; returns how many sources it read.
int expect_short_functions(const std::string& folder) {
    const std::vector<fs::path> sources = sources_below(folder);
    for (const fs::path& path : sources)
        for (const LongFunction& f : long_functions(read_text(path), max_function_lines))
            ADD_FAILURE() << fs::relative(path, source_dir).string() << ":" << f.first_line << ": "
                          << f.name << " is " << f.lines << " lines long (at most "
                          << max_function_lines << ")";
    return static_cast<int>(sources.size());
}

/// Fails once per source below `folder` longer than `max_file_lines`; returns how many
/// sources it read.
int expect_short_files(const std::string& folder) {
    const std::vector<fs::path> sources = sources_below(folder);
    for (const fs::path& path : sources) {
        const int lines = line_count(read_text(path));
        if (lines > max_file_lines)
            ADD_FAILURE() << fs::relative(path, source_dir).string() << ":1: " << lines
                          << " lines long (at most " << max_file_lines << ")";
    }
    return static_cast<int>(sources.size());
}

TEST(Structure, LibraryFunctionsAreShort) { EXPECT_GT(expect_short_functions("include"), 50); }

TEST(Structure, ExampleFunctionsAreShort) { EXPECT_GT(expect_short_functions("examples"), 10); }

TEST(Structure, LibraryFilesAreShort) { EXPECT_GT(expect_short_files("include"), 50); }

TEST(Structure, ExampleFilesAreShort) { EXPECT_GT(expect_short_files("examples"), 10); }

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
        R"re([0-9] ?(ns|us|ms)\b|[0-9.]+ ?x (faster|slower)|[0-9] ?% (faster|slower|longer|shorter|dearer|cheaper))re");
    return std::regex_search(comment, timing);
}

TEST(Structure, FindsTimingsInComments) {
    EXPECT_TRUE(quotes_a_timing("// took 8.4 ms against 6.6"));
    EXPECT_TRUE(quotes_a_timing("/// 4x slower draws"));
    EXPECT_TRUE(quotes_a_timing("// 10-20 % slower with g++ 12"));
    EXPECT_TRUE(quotes_a_timing("// (the draw took 30 % longer)"));
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
