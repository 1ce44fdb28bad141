#include "conftrack/core/TomlInputCheck.hpp"

#include "conftrack/core/Error.hpp"

namespace conftrack {

namespace {

std::string hexByte(unsigned char byte) {
  static constexpr char kHex[] = "0123456789abcdef";
  return std::string("0x") + kHex[byte >> 4] + kHex[byte & 0xf];
}

bool isBareKeyCharacter(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
         (c >= '0' && c <= '9') || c == '_' || c == '-';
}

/// Throws unless every '}' outside strings and comments closes an inline
/// table ('{' on top of the bracket stack), as in any valid TOML.
void requireMatchedBraces(std::string_view text, const std::string& file) {
  enum class State {
    eCode,
    eComment,
    eBasic,
    eLiteral,
    eMultiBasic,
    eMultiLiteral
  };
  State state = State::eCode;
  std::string brackets;  // open '[' and '{', innermost last
  std::size_t line = 1;
  auto startsWith = [&](std::size_t i, std::string_view s) {
    return text.substr(i, s.size()) == s;
  };
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
      // Single-line strings and comments end here (an unterminated string
      // is toml++'s to report).
      if (state == State::eComment || state == State::eBasic ||
          state == State::eLiteral) {
        state = State::eCode;
      }
      continue;
    }
    switch (state) {
      case State::eCode:
        if (c == '#') {
          state = State::eComment;
        } else if (c == '"' || c == '\'') {
          const bool multi = startsWith(i, c == '"' ? "\"\"\"" : "'''");
          state = c == '"' ? (multi ? State::eMultiBasic : State::eBasic)
                           : (multi ? State::eMultiLiteral : State::eLiteral);
          i += multi ? 2 : 0;
        } else if (c == '[' || c == '{') {
          brackets.push_back(c);
        } else if (c == ']' && !brackets.empty() && brackets.back() == '[') {
          brackets.pop_back();
        } else if (c == '}') {
          if (brackets.empty() || brackets.back() != '{') {
            throw InputError(location(file, line),
                             "TOML syntax: '}' without a matching '{'");
          }
          brackets.pop_back();
        }
        break;
      case State::eComment:
        break;
      case State::eBasic:
      case State::eMultiBasic:
        if (c == '\\') {
          // An escaped character (a line-ending backslash continues the
          // line: count it).
          if (i + 1 < text.size() && text[i + 1] == '\n') {
            ++line;
          }
          ++i;
        } else if (state == State::eBasic && c == '"') {
          state = State::eCode;
        } else if (state == State::eMultiBasic && startsWith(i, "\"\"\"")) {
          state = State::eCode;
          i += 2;
        }
        break;
      case State::eLiteral:
        if (c == '\'') {
          state = State::eCode;
        }
        break;
      case State::eMultiLiteral:
        if (startsWith(i, "'''")) {
          state = State::eCode;
          i += 2;
        }
        break;
    }
  }
}

}  // namespace

void requireSafeToml(std::string_view text, const std::string& file) {
  std::size_t line = 1;
  bool lineStart = true;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto byte = static_cast<unsigned char>(text[i]);
    if (byte >= 0x80) {
      throw InputError(location(file, line),
                       "non-ASCII byte " + hexByte(byte) +
                           " (conftrack config files are ASCII)");
    }
    if ((byte < 0x20 && byte != '\t' && byte != '\n' && byte != '\r') ||
        byte == 0x7f) {
      throw InputError(
          location(file, line),
          "control character " + hexByte(byte) + " (not allowed in TOML)");
    }
    if (byte == '\n') {
      ++line;
      lineStart = true;
      continue;
    }
    if (lineStart && byte == '[') {
      // The first key of a table header: "[ key", "[[ key", "[ \"key\"".
      std::size_t k = i + 1;
      auto skipBlanks = [&] {
        while (k < text.size() && (text[k] == ' ' || text[k] == '\t')) {
          ++k;
        }
      };
      skipBlanks();
      if (k < text.size() && text[k] == '[') {
        ++k;
        skipBlanks();
      }
      if (k < text.size() && !isBareKeyCharacter(text[k]) && text[k] != '"' &&
          text[k] != '\'' && text[k] != ']') {
        throw InputError(location(file, line),
                         "TOML syntax: expected a key after '[' of a table "
                         "header");
      }
    }
    if (byte != ' ' && byte != '\t') {
      lineStart = false;
    }
  }
  requireMatchedBraces(text, file);
}

}  // namespace conftrack
