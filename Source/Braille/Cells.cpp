#include "Braille/Cells.h"
#include "Core/AtomicFile.h"
#include "Core/Errors.h"
#include <liblouis/liblouis.h>
#include <algorithm>
#include <array>
#include <cctype>
#include <cstdio>
#include <mutex>
#include <set>
#include <stdexcept>

namespace armadillo::braille {

Dots dotsFromNumbers(std::string_view numbers)
{
    Dots d = 0;
    for (char c : numbers) {
        if (c == '0' && numbers.size() == 1) return 0;
        if (c < '1' || c > '6') throw std::invalid_argument("dot numbers are 1..6, not '" + std::string(numbers) + "'");
        d = static_cast<Dots>(d | dot(c - '0'));
    }
    return d;
}

std::string dotNumbers(Dots cell)
{
    std::string s;
    for (int d = 1; d <= 8; ++d)
        if (cell & (1u << (d - 1))) s += static_cast<char>('0' + d);
    return s.empty() ? "0" : s;
}

namespace {

void appendUtf8(std::string& out, char32_t c)
{
    if (c < 0x80) {
        out += static_cast<char>(c);
    } else if (c < 0x800) {
        out += static_cast<char>(0xC0 | (c >> 6));
        out += static_cast<char>(0x80 | (c & 0x3F));
    } else if (c < 0x10000) {
        out += static_cast<char>(0xE0 | (c >> 12));
        out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
        out += static_cast<char>(0x80 | (c & 0x3F));
    } else {
        out += static_cast<char>(0xF0 | (c >> 18));
        out += static_cast<char>(0x80 | ((c >> 12) & 0x3F));
        out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
        out += static_cast<char>(0x80 | (c & 0x3F));
    }
}

/// Strict UTF-8 → code points; InputError on malformed input, naming the source, the line and
/// the byte within the line.
std::u32string decodeUtf8(std::string_view s, const std::string& source)
{
    std::u32string out;
    std::size_t i = 0;
    long line = 1;
    std::size_t lineStart = 0;
    auto bad = [&](const char* what) {
        throw core::InputError(source, line, "", std::string(what) + " at byte " + std::to_string(i - lineStart + 1) + " of the line");
    };
    while (i < s.size()) {
        const auto b0 = static_cast<unsigned char>(s[i]);
        int extra = 0;
        char32_t c = 0;
        if (b0 < 0x80) { c = b0; }
        else if ((b0 & 0xE0) == 0xC0) { c = b0 & 0x1F; extra = 1; }
        else if ((b0 & 0xF0) == 0xE0) { c = b0 & 0x0F; extra = 2; }
        else if ((b0 & 0xF8) == 0xF0) { c = b0 & 0x07; extra = 3; }
        else bad("invalid UTF-8");
        if (i + static_cast<std::size_t>(extra) >= s.size()) bad("truncated UTF-8 sequence");
        for (int k = 1; k <= extra; ++k) {
            const auto b = static_cast<unsigned char>(s[i + static_cast<std::size_t>(k)]);
            if ((b & 0xC0) != 0x80) bad("invalid UTF-8");
            c = (c << 6) | (b & 0x3F);
        }
        static constexpr std::array<char32_t, 4> kMin {0, 0x80, 0x800, 0x10000};
        if (c < kMin[static_cast<std::size_t>(extra)] || c > 0x10FFFF || (c >= 0xD800 && c <= 0xDFFF)) bad("invalid UTF-8");
        if (c == U'\0') bad("a NUL byte (not text)");
        out += c;
        i += static_cast<std::size_t>(extra) + 1;
        if (c == U'\n') {
            ++line;
            lineStart = i;
        }
    }
    return out;
}

std::string encodeUtf8(const std::u32string& s)
{
    std::string out;
    for (char32_t c : s) appendUtf8(out, c);
    return out;
}

bool isSpaceChar(char32_t c) { return c == U' ' || c == U'\t' || c == U'\r' || c == 0xA0; }

// liblouis is not thread-safe and reports table errors through a global log callback: every
// call goes through this lock, and the callback collects the messages for our error text.
std::mutex gLouisMutex;
std::string gLouisLog;

void collectLouisLog(logLevels level, const char* message)
{
    if (level >= LOU_LOG_ERROR && message) {
        if (!gLouisLog.empty()) gLouisLog += "; ";
        gLouisLog += message;
    }
}

class LouisSession {
public:
    LouisSession() : lock_(gLouisMutex)
    {
        gLouisLog.clear();
        lou_registerLogCallback(collectLouisLog);
    }
    ~LouisSession() { lou_registerLogCallback(nullptr); }
    std::string log() const { return gLouisLog; }

private:
    std::lock_guard<std::mutex> lock_;
};

struct LouisOutput {
    std::vector<widechar> cells;
    std::vector<int> inputPos;   ///< per output cell: index of the input character it came from
};

/// One lou_translate call with dot-pattern output; grows the buffer until all input is consumed.
bool louisTranslate(const std::string& table, const std::vector<widechar>& in, int mode, LouisOutput& out)
{
    std::size_t capacity = in.size() * 8 + 64;
    for (int attempt = 0; attempt < 6; ++attempt, capacity *= 4) {
        int inLen = static_cast<int>(in.size());
        int outLen = static_cast<int>(capacity);
        out.cells.assign(capacity, 0);
        out.inputPos.assign(capacity, 0);
        std::vector<int> outputPos(in.size() + 1, 0);
        if (!lou_translate(table.c_str(), in.data(), &inLen, out.cells.data(), &outLen, nullptr, nullptr,
                           outputPos.data(), out.inputPos.data(), nullptr, dotsIO | ucBrl | mode))
            return false;
        if (inLen == static_cast<int>(in.size()) && outLen < static_cast<int>(capacity)) {
            out.cells.resize(static_cast<std::size_t>(outLen));
            out.inputPos.resize(static_cast<std::size_t>(outLen));
            return true;
        }
    }
    return false;
}

std::string describeChar(char32_t c)
{
    char code[16];
    std::snprintf(code, sizeof code, "U+%04X", static_cast<unsigned>(c));
    std::string s = code;
    if (c >= 0x20 && c != 0x7F) {
        s += " '";
        appendUtf8(s, c);
        s += "'";
    }
    return s;
}

void addSpace(BrailleMessage& m)
{
    if (!m.symbols.empty() && !m.symbols.back().isSpace()) m.symbols.push_back({" ", {0}});
}

void trimTrailingSpace(BrailleMessage& m)
{
    while (!m.symbols.empty() && m.symbols.back().isSpace()) m.symbols.pop_back();
}

BrailleMessage translateLine(const std::u32string& line, std::size_t lineNumber, const std::string& table, const std::string& source)
{
    BrailleMessage message;
    std::vector<widechar> in(line.begin(), line.end());
    if (in.empty()) return message;

    // A character the table does not define would come out as "\x2603" spelled in braille: refuse it
    // instead, naming it, so a reader never feels an escape sequence.
    std::set<char32_t> checked;
    for (std::size_t i = 0; i < line.size(); ++i) {
        const char32_t c = line[i];
        if (isSpaceChar(c) || !checked.insert(c).second) continue;
        LouisOutput single;
        const std::vector<widechar> one {static_cast<widechar>(c)};
        if (!louisTranslate(table, one, noUndefined, single) || single.cells.empty())
            throw core::InputError(source, static_cast<long>(lineNumber), "",
                             "character " + describeChar(c) + " at position " + std::to_string(i + 1) +
                                 " cannot be translated with table '" + table + "'");
    }

    LouisOutput out;
    if (!louisTranslate(table, in, 0, out))
        throw core::InputError(source, static_cast<long>(lineNumber), "", "liblouis could not translate this line with table '" + table + "'");

    const std::size_t n = out.cells.size();
    for (std::size_t i = 0; i < n;) {
        // A group = output cells that come from the same input position (a letter with its
        // capital sign, a contraction covering several letters).
        std::size_t j = i + 1;
        while (j < n && out.inputPos[j] == out.inputPos[i]) ++j;
        const int start = out.inputPos[i];
        int end = static_cast<int>(line.size());
        for (std::size_t k = j; k < n; ++k)
            if (out.inputPos[k] > start) { end = std::min(end, out.inputPos[k]); break; }
        std::u32string print = line.substr(static_cast<std::size_t>(std::clamp(start, 0, static_cast<int>(line.size()))),
                                           static_cast<std::size_t>(std::max(0, end - start)));
        while (!print.empty() && isSpaceChar(print.back())) print.pop_back();
        while (!print.empty() && isSpaceChar(print.front())) print.erase(print.begin());

        BrailleSymbol symbol {encodeUtf8(print), {}};
        for (std::size_t k = i; k < j; ++k) {
            const widechar w = out.cells[k];
            if ((w & 0xFF00u) != 0x2800u)
                throw core::InputError(source, static_cast<long>(lineNumber), "",
                                 "table '" + table + "' produced a non-braille character " + describeChar(static_cast<char32_t>(w)));
            const unsigned bits = w & 0xFFu;
            if (bits & 0xC0u)
                throw core::InputError(source, static_cast<long>(lineNumber), "",
                                 "table '" + table + "' uses dots 7-8 (for " + describeChar(line[static_cast<std::size_t>(std::max(start, 0))]) +
                                     "); the three-row display shows six-dot braille only: choose a six-dot table");
            if (bits == 0) {
                if (!symbol.cells.empty()) message.symbols.push_back(symbol);
                symbol.cells.clear();
                addSpace(message);
            } else {
                symbol.cells.push_back(static_cast<Dots>(bits));
            }
        }
        if (!symbol.cells.empty()) message.symbols.push_back(symbol);
        i = j;
    }
    trimTrailingSpace(message);
    return message;
}

} // namespace

std::string unicodeCell(Dots cell)
{
    std::string s;
    appendUtf8(s, static_cast<char32_t>(0x2800 + cell));
    return s;
}

std::size_t BrailleDocument::cellCount() const noexcept
{
    std::size_t n = 0;
    for (const auto& m : messages)
        for (const auto& s : m.symbols) n += s.cells.size();
    return n;
}

std::string defaultTable(int grade)
{
    return grade == 2 ? "en-ueb-g2.ctb" : "en-ueb-g1.ctb";
}

BrailleDocument translateText(std::string_view utf8, const TranslationOptions& options)
{
    if (options.grade != 1 && options.grade != 2)
        throw core::InputError(options.source, 0, "", "braille grade must be 1 or 2, not " + std::to_string(options.grade));
    BrailleDocument doc;
    doc.table = options.table.empty() ? defaultTable(options.grade) : options.table;
    if (doc.table.find_first_of("\n\r") != std::string::npos)
        throw core::InputError(options.source, 0, "", "bad table name");

    std::u32string text = decodeUtf8(utf8, options.source);
    for (auto& c : text) {
        if (isSpaceChar(c)) c = U' ';   // tabs, CR, no-break spaces: all a word gap
        if (!options.capitals && c >= U'A' && c <= U'Z') c = c - U'A' + U'a';
    }

    LouisSession session;
    if (!lou_getTable(doc.table.c_str())) {
        const std::string why = session.log();
        throw core::InputError(doc.table, 0, "", "liblouis cannot load braille table '" + doc.table + "'" + (why.empty() ? "" : ": " + why));
    }
    std::size_t lineNumber = 1;
    std::size_t begin = 0;
    while (begin <= text.size()) {
        std::size_t end = text.find(U'\n', begin);
        if (end == std::u32string::npos) end = text.size();
        BrailleMessage m = translateLine(text.substr(begin, end - begin), lineNumber, doc.table, options.source);
        if (!m.symbols.empty()) doc.messages.push_back(std::move(m));
        begin = end + 1;
        ++lineNumber;
    }
    return doc;
}

// --- Braille ASCII --------------------------------------------------------------------------------

namespace {
// North American Braille ASCII: the cell of each character from 0x20 (space) to 0x5F ('_'),
// written as dot numbers. (The mapping itself is the standard one every embosser and .brf file
// uses; it is also checked against liblouis's own en-us-brf.dis display table in the tests.)
constexpr std::array<const char*, 64> kBrfDots {
    "0",     "2346",  "5",    "3456",  "1246",  "146",   "12346", "3",      // space ! " # $ % & '
    "12356", "23456", "16",   "346",   "6",     "36",    "46",    "34",     // ( ) * + , - . /
    "356",   "2",     "23",   "25",    "256",   "26",    "235",   "2356",   // 0 1 2 3 4 5 6 7
    "236",   "35",    "156",  "56",    "126",   "123456", "345",  "1456",   // 8 9 : ; < = > ?
    "4",     "1",     "12",   "14",    "145",   "15",    "124",   "1245",   // @ A B C D E F G
    "125",   "24",    "245",  "13",    "123",   "134",   "1345",  "135",    // H I J K L M N O
    "1234",  "12345", "1235", "234",   "2345",  "136",   "1236",  "2456",   // P Q R S T U V W
    "1346",  "13456", "1356", "246",   "1256",  "12456", "45",    "456",    // X Y Z [ \ ] ^ _
};

struct BrfTables {
    std::array<Dots, 64> dots {};
    std::array<char, 64> charOf {};
    BrfTables()
    {
        for (std::size_t i = 0; i < 64; ++i) {
            dots[i] = dotsFromNumbers(kBrfDots[i]);
            charOf[dots[i]] = static_cast<char>(0x20 + i);
        }
    }
};
const BrfTables& brfTables()
{
    static const BrfTables tables;
    return tables;
}
} // namespace

bool brfToDots(char c, Dots& out) noexcept
{
    auto u = static_cast<unsigned char>(c);
    if (u >= 0x60 && u <= 0x7E) u = static_cast<unsigned char>(u - 0x20);   // a..z `{|}~ as A..Z @[\]^
    if (u < 0x20 || u > 0x5F) return false;
    out = brfTables().dots[u - 0x20];
    return true;
}

char dotsToBrf(Dots cell) noexcept { return brfTables().charOf[cell & 0x3F]; }

BrailleDocument parseBrf(std::string_view content, const std::string& source)
{
    BrailleDocument doc;
    doc.table = "brf";
    BrailleMessage message;
    auto endMessage = [&] {
        trimTrailingSpace(message);
        if (!message.symbols.empty()) doc.messages.push_back(std::move(message));
        message = {};
    };
    long line = 1, column = 0;
    bool lineBlank = true;
    for (std::size_t i = 0; i < content.size(); ++i) {
        const char c = content[i];
        ++column;
        if (c == '\r') continue;
        if (c == '\n' || c == '\f') {
            if (c == '\f' || lineBlank) endMessage();   // page break or blank line: a new message
            else addSpace(message);
            if (c == '\n') { ++line; column = 0; }
            lineBlank = true;
            continue;
        }
        if (c == '\x1A' && i + 1 == content.size()) break;   // DOS end-of-file marker some embossers write
        Dots d = 0;
        if (!brfToDots(c, d)) {
            char what[48];
            std::snprintf(what, sizeof what, "byte 0x%02X is not Braille ASCII", static_cast<unsigned>(static_cast<unsigned char>(c)));
            throw core::InputError(source, line, "", std::string(what) + " (column " + std::to_string(column) + ")");
        }
        if (d == 0) {
            addSpace(message);
            continue;
        }
        lineBlank = false;
        message.symbols.push_back({std::string(1, dotsToBrf(d)), {d}});
    }
    endMessage();
    if (doc.messages.empty()) throw core::InputError(source, 0, "", "no braille in this file");
    return doc;
}

BrailleDocument readBrfFile(const std::string& path)
{
    return parseBrf(core::readWholeFile(path), path);
}

BrailleDocument loadDocument(const std::string& textOrFile, const TranslationOptions& options)
{
    if (!textOrFile.empty() && textOrFile.front() == '@') {
        const std::string path = textOrFile.substr(1);
        std::string ext = path.size() >= 4 ? path.substr(path.size() - 4) : "";
        std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
        if (ext == ".brf") return readBrfFile(path);
        TranslationOptions fromFile = options;
        fromFile.source = path;   // messages name the file and its line
        return translateText(core::readWholeFile(path), fromFile);
    }
    return translateText(textOrFile, options);
}

} // namespace armadillo::braille
