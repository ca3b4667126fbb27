// A recursive-descent parser for the grammar in expression_parser.hpp, emitting postfix code as it
// goes. One function per grammar rule; the recursion goes through parentheses only (signs are a
// loop), so the nesting limit bounds the stack.
#include <eulervop/scene/expression_parser.hpp>

#include <eulervop/scene/decimal.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <optional>

namespace eulervop::scene {

namespace {

enum class tok { end, number, identifier, plus, minus, star, slash, caret, lparen, rparen, comma, bad };

struct token {
  tok kind = tok::end;
  std::size_t begin = 0, end = 0;  // byte offsets into the text
};

bool is_digit(char c) { return c >= '0' && c <= '9'; }
bool is_letter(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_'; }
bool is_identifier_char(char c) { return is_letter(c) || is_digit(c); }
bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v'; }
bool is_operator(tok k) {
  return k == tok::plus || k == tok::minus || k == tok::star || k == tok::slash || k == tok::caret;
}

// The length of the UTF-8 sequence at s[i], and whether it is well formed (an unexpected
// character is quoted whole, and only then, so the message stays valid UTF-8).
std::pair<std::size_t, bool> utf8_sequence(std::string_view s, std::size_t i) {
  const auto lead = static_cast<unsigned char>(s[i]);
  std::size_t n = 1;
  if (lead >= 0xC2 && lead <= 0xDF) n = 2;
  else if (lead >= 0xE0 && lead <= 0xEF) n = 3;
  else if (lead >= 0xF0 && lead <= 0xF4) n = 4;
  else return {1, lead < 0x80};
  if (i + n > s.size()) return {1, false};
  for (std::size_t k = 1; k < n; ++k)
    if ((static_cast<unsigned char>(s[i + k]) & 0xC0) != 0x80) return {1, false};
  return {n, true};
}

// The culprit as a message quotes it: control characters (and, unless keep_utf8, every byte
// above ASCII) as \xHH, so what() stays one printable line.
std::string printable(std::string_view s, bool keep_utf8 = false) {
  std::string out;
  for (char c : s) {
    const auto b = static_cast<unsigned char>(c);
    if (b < 0x20 || b == 0x7F || (b >= 0x80 && !keep_utf8)) out += fmt::format("\\x{:02x}", b);
    else out += c;
  }
  return out;
}

// The token that starts at or after byte i (after blanks).
token lex(std::string_view s, std::size_t i) {
  const std::size_t n = s.size();
  while (i < n && is_space(s[i])) ++i;
  if (i == n) return {tok::end, i, i};
  const char c = s[i];
  auto single = [&](tok k) { return token{k, i, i + 1}; };
  switch (c) {
    case '+': return single(tok::plus);
    case '-': return single(tok::minus);
    case '*': return single(tok::star);
    case '/': return single(tok::slash);
    case '^': return single(tok::caret);
    case '(': return single(tok::lparen);
    case ')': return single(tok::rparen);
    case ',': return single(tok::comma);
    default: break;
  }
  if (is_digit(c) || c == '.') {
    // digits ['.' digits] [exponent]. An 'e' that starts a word ("2exp(t)") is not an exponent:
    // the number ends before it and the word is the next operand. Any other 'e' without digits
    // ("1e", "2e+") and glued dots ("1.2.3") stay in the token, which parse_decimal rejects.
    std::size_t j = i;
    while (j < n && is_digit(s[j])) ++j;
    if (j < n && s[j] == '.') {
      ++j;
      while (j < n && is_digit(s[j])) ++j;
    }
    if (j < n && (s[j] == 'e' || s[j] == 'E')) {
      std::size_t k = j + 1;
      if (k < n && (s[k] == '+' || s[k] == '-')) ++k;
      if (k < n && is_digit(s[k])) {
        while (k < n && is_digit(s[k])) ++k;
        j = k;
      } else if (!(j + 1 < n && is_identifier_char(s[j + 1]))) {
        j = k;
      }
    }
    while (j < n && (is_digit(s[j]) || s[j] == '.')) ++j;
    return {tok::number, i, j};
  }
  if (is_letter(c)) {
    std::size_t j = i + 1;
    while (j < n && is_identifier_char(s[j])) ++j;
    return {tok::identifier, i, j};
  }
  return {tok::bad, i, i + utf8_sequence(s, i).first};
}

struct function_name {
  std::string_view name;
  expression_op op;
};
constexpr function_name functions[] = {{"sin", expression_op::sin},
                                       {"cos", expression_op::cos},
                                       {"exp", expression_op::exp},
                                       {"log", expression_op::log},
                                       {"sqrt", expression_op::sqrt},
                                       {"tanh", expression_op::tanh},
                                       {"atan", expression_op::atan},
                                       {"sinh", expression_op::sinh},
                                       {"cosh", expression_op::cosh}};

std::optional<expression_op> function_op(std::string_view name) {
  for (const function_name& f : functions)
    if (f.name == name) return f.op;
  return std::nullopt;
}

class parser {
 public:
  parser(std::string_view text, const expression_variables& vars) : text_(text), vars_(vars) {}

  expression run() {
    if (text_.size() > max_expression_length)
      throw expression_error(fmt::format("expression too long at column {}: {} bytes, at most {}",
                                         column(max_expression_length), text_.size(), max_expression_length),
                             "", column(max_expression_length));
    out_.text = std::string(text_);
    cur_ = lex(text_, 0);
    sum();
    if (cur_.kind != tok::end) after_operand(nullptr);
    out_.stack_depth = most_;
    return std::move(out_);
  }

 private:
  // sum := product (('+' | '-') product)*
  void sum() {
    product();
    while (cur_.kind == tok::plus || cur_.kind == tok::minus) {
      const expression_op op = cur_.kind == tok::plus ? expression_op::add : expression_op::sub;
      advance();
      product();
      emit(op);
    }
  }

  // product := signed (('*' | '/') signed)*
  void product() {
    signed_power();
    while (cur_.kind == tok::star || cur_.kind == tok::slash) {
      const expression_op op = cur_.kind == tok::star ? expression_op::mul : expression_op::div;
      advance();
      signed_power();
      emit(op);
    }
  }

  // signed := ('+' | '-')* power. -(-x) = x exactly, so only the parity of the minus signs counts.
  void signed_power() {
    const bool negative = signs();
    power();
    if (negative) emit(expression_op::neg);
  }

  bool signs() {
    bool negative = false;
    while (cur_.kind == tok::plus || cur_.kind == tok::minus) {
      if (cur_.kind == tok::minus) negative = !negative;
      advance();
    }
    return negative;
  }

  // power := primary ('^' integer)?
  void power() {
    primary();
    if (cur_.kind != tok::caret) return;
    advance();
    emit(expression_op::pow, integer_exponent());
    if (cur_.kind == tok::caret)
      fail("chained power", "^", cur_.begin, "use parentheses, as in (x^2)^3");
  }

  // integer := ['+' | '-'] digits | '(' ['+' | '-'] digits ')'
  std::int32_t integer_exponent() {
    const std::size_t start = cur_.begin;
    token t = cur_;
    const bool parenthesized = t.kind == tok::lparen;
    if (parenthesized) t = lex(text_, t.end);
    bool negative = false;
    if (t.kind == tok::plus || t.kind == tok::minus) {
      negative = t.kind == tok::minus;
      t = lex(text_, t.end);
    }
    const std::string_view digits = text_.substr(t.begin, t.end - t.begin);
    const bool is_integer = t.kind == tok::number && std::all_of(digits.begin(), digits.end(), is_digit);
    token last = t;
    if (is_integer && parenthesized) last = lex(text_, t.end);
    if (!is_integer || (parenthesized && last.kind != tok::rparen)) {
      // Not an integer as written: parse the operand anyway, to quote it whole ("0.5", "t",
      // "(1/2)"), or to report what is wrong with it first.
      signs();
      primary();
      fail("non-integer power", text_.substr(start, prev_.end - start), start,
           "the exponent must be an integer as written, as in x^2 or x^-1");
    }
    const std::string_view written = text_.substr(start, last.end - start);
    const std::size_t first = std::min(digits.find_first_not_of('0'), digits.size());
    const std::string_view significant = digits.substr(first);
    int magnitude = 0;
    for (char c : significant) {
      if (significant.size() > 4) break;  // more than max_expression_power
      magnitude = 10 * magnitude + (c - '0');
    }
    if (significant.size() > 4 || magnitude > max_expression_power)
      fail("power too large", written, start, fmt::format("at most {} in magnitude", max_expression_power));
    prev_ = last;
    cur_ = lex(text_, last.end);
    return negative ? -magnitude : magnitude;
  }

  // primary := number | 'pi' | variable | function '(' sum ')' | '(' sum ')'
  void primary() {
    const std::string_view word = text_.substr(cur_.begin, cur_.end - cur_.begin);
    switch (cur_.kind) {
      case tok::number: {
        const decimal_parse_result parsed = parse_decimal(word);
        if (!parsed.number) fail("invalid number", word, cur_.begin, std::string(describe(parsed.problem)));
        emit(expression_op::constant, constant_index(parsed.number->text));
        advance();
        return;
      }
      case tok::identifier: {
        const token name = cur_;
        advance();
        const std::optional<expression_op> function = function_op(word);
        if (cur_.kind == tok::lparen) {
          if (!function)
            fail("unknown function", word, name.begin, "the functions are sin, cos, exp, log, sqrt, tanh, atan, sinh and cosh");
          call(name, *function);
          return;
        }
        if (function) fail("missing `(` after function", word, name.begin, fmt::format("write {}(...)", word));
        if (word == "pi") {
          emit(expression_op::pi);
          return;
        }
        for (std::size_t slot = 0; slot < vars_.names.size(); ++slot) {
          if (!vars_.names[slot].empty() && vars_.names[slot] == word) {
            out_.uses |= 1u << slot;
            emit(expression_op::variable, static_cast<std::int32_t>(slot));
            return;
          }
        }
        fail("unknown identifier", word, name.begin);
      }
      case tok::lparen: {
        const token open = cur_;
        open_parenthesis(open);
        advance();
        sum();
        close_parenthesis(open);
        return;
      }
      default: missing_operand();
    }
  }

  // function '(' sum ')', counting the arguments so sin() and sin(t, 1) say what they got.
  void call(const token& name, expression_op op) {
    const token open = cur_;
    open_parenthesis(open);
    advance();
    int arguments = 0;
    if (cur_.kind != tok::rparen) {
      sum();
      arguments = 1;
      while (cur_.kind == tok::comma) {
        advance();
        sum();
        ++arguments;
      }
    }
    const std::size_t close = cur_.end;
    close_parenthesis(open);
    if (arguments != 1)
      fail(fmt::format("{} takes 1 argument, got {}:", text_.substr(name.begin, name.end - name.begin), arguments),
           text_.substr(name.begin, close - name.begin), name.begin);
    emit(op);
  }

  void open_parenthesis(const token& open) {
    if (++depth_ > max_expression_nesting)
      fail("nesting too deep", "(", open.begin,
           fmt::format("at most {} levels of parentheses", max_expression_nesting));
  }

  void close_parenthesis(const token& open) {
    if (cur_.kind != tok::rparen) after_operand(&open);
    advance();
    --depth_;
  }

  // An operand ended, and the next token neither continues nor closes it. open: the parenthesis
  // being closed, if any.
  [[noreturn]] void after_operand(const token* open) {
    const std::string_view word = text_.substr(cur_.begin, cur_.end - cur_.begin);
    switch (cur_.kind) {
      case tok::end:
        if (open) fail("unbalanced parentheses: missing `)` for", "(", open->begin);
        break;
      case tok::rparen: fail("unbalanced parentheses: unexpected", ")", cur_.begin);
      case tok::number:
      case tok::identifier:
      case tok::lparen: fail("two operands in a row: missing operator before", word, cur_.begin);
      case tok::comma: fail("unexpected", ",", cur_.begin, "a comma separates a function's arguments only");
      case tok::bad: unexpected_character();
      default: break;
    }
    fail("unexpected", word, cur_.begin);
  }

  // An operand was expected at cur_ and none starts there.
  [[noreturn]] void missing_operand() {
    const std::string_view before = text_.substr(prev_.begin, prev_.end - prev_.begin);
    const bool after_operator = has_prev_ && is_operator(prev_.kind);
    switch (cur_.kind) {
      case tok::end:
      case tok::rparen:
      case tok::comma:
        if (!has_prev_) {
          if (cur_.kind == tok::end) throw expression_error("empty expression", "", 1);
          if (cur_.kind == tok::rparen) fail("unbalanced parentheses: unexpected", ")", cur_.begin);
        }
        if (after_operator) fail("dangling operator", before, prev_.begin);
        if (prev_.kind == tok::comma) fail("missing argument after", ",", prev_.begin);
        if (prev_.kind == tok::lparen) {
          if (cur_.kind == tok::rparen) fail("empty parentheses", "()", prev_.begin);
          if (cur_.kind == tok::end) fail("unbalanced parentheses: missing `)` for", "(", prev_.begin);
        }
        fail("unexpected", cur_.kind == tok::comma ? "," : ")", cur_.begin);
      case tok::star:
      case tok::slash:
      case tok::caret:
        fail("dangling operator", text_.substr(cur_.begin, 1), cur_.begin);
      case tok::bad: unexpected_character();
      default: fail("unexpected", text_.substr(cur_.begin, cur_.end - cur_.begin), cur_.begin);
    }
  }

  [[noreturn]] void unexpected_character() {
    const auto [length, well_formed] = utf8_sequence(text_, cur_.begin);
    fail("unexpected character", printable(text_.substr(cur_.begin, length), well_formed), cur_.begin);
  }

  // "<what> `<culprit>` at column <n>[: <detail>]"
  [[noreturn]] void fail(std::string_view what, std::string_view culprit, std::size_t offset,
                         std::string_view detail = {}) {
    std::string quoted = printable(culprit, true);
    const std::size_t col = column(offset);
    std::string message = fmt::format("{} `{}` at column {}", what, quoted, col);
    if (!detail.empty()) message += fmt::format(": {}", detail);
    throw expression_error(message, std::move(quoted), col);
  }

  // 1-based column of a byte offset, in characters (UTF-8 continuation bytes do not count).
  std::size_t column(std::size_t offset) const {
    std::size_t col = 1;
    for (std::size_t i = 0; i < offset && i < text_.size(); ++i)
      if ((static_cast<unsigned char>(text_[i]) & 0xC0) != 0x80) ++col;
    return col;
  }

  void advance() {
    prev_ = cur_;
    has_prev_ = true;
    cur_ = lex(text_, cur_.end);
  }

  std::int32_t constant_index(const std::string& canonical) {
    const auto it = std::find(out_.constants.begin(), out_.constants.end(), canonical);
    if (it != out_.constants.end()) return static_cast<std::int32_t>(it - out_.constants.begin());
    out_.constants.push_back(canonical);
    return static_cast<std::int32_t>(out_.constants.size() - 1);
  }

  void emit(expression_op op, std::int32_t arg = 0) {
    out_.code.push_back({op, arg});
    switch (op) {
      case expression_op::constant:
      case expression_op::pi:
      case expression_op::variable: most_ = std::max(most_, ++stack_); break;
      case expression_op::add:
      case expression_op::sub:
      case expression_op::mul:
      case expression_op::div: --stack_; break;
      default: break;
    }
  }

  std::string_view text_;
  const expression_variables& vars_;
  expression out_;
  token cur_, prev_;
  bool has_prev_ = false;
  std::size_t depth_ = 0;            // parentheses open
  std::size_t stack_ = 0, most_ = 0;  // values the program holds at this point, and at most
};

}  // namespace

expression parse_expression(std::string_view text, const expression_variables& vars) {
  return parser(text, vars).run();
}

}  // namespace eulervop::scene
