#include "roadcross/preprocess/parameter_file.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "roadcross/preprocess/common/errors.hpp"

namespace roadcross::preprocess {

namespace {

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

/// The line without a trailing '#' or ';' comment (values are numbers: no quoting to mind).
std::string_view strip_comment(std::string_view line) {
  return trim(line.substr(0, line.find_first_of("#;")));
}

/// A TOML/INI number: "10", "-4", "0.75", "1e-05", "+3", "1_000" is not accepted.
std::optional<double> parse_number(std::string_view text) {
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  double value = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(value)) {
    return std::nullopt;
  }
  return value;
}

class TextParser {
 public:
  TextParser(const std::string& name, Parameters& parameters)
      : name_(name), specs_(parameters.specs()) {
    for (const ParameterSpec& spec : specs_) sections_.insert(spec.section);
  }

  void line(std::string_view raw, std::size_t number) {
    number_ = number;
    const std::string_view text = strip_comment(raw);
    if (text.empty()) return;
    if (text.front() == '[') return section(text);
    const std::size_t equals = text.find('=');
    if (equals == std::string_view::npos) fail("", "expected 'name = value' or '[section]'");
    assign(trim(text.substr(0, equals)), trim(text.substr(equals + 1)));
  }

 private:
  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw ParameterError(name_ + ":" + std::to_string(number_) + ": " +
                         (key.empty() ? "" : key + ": ") + what);
  }

  void section(std::string_view text) {
    if (text.back() != ']') fail("", "a section header must look like [section]");
    const std::string name(trim(text.substr(1, text.size() - 2)));
    if (!sections_.count(name)) fail("[" + name + "]", "unknown section" + known_sections());
    section_ = name;
  }

  std::string known_sections() const {
    std::string out = " (known:";
    for (const std::string& s : sections_) out += " " + s;
    return out + ")";
  }

  void assign(std::string_view name, std::string_view value_text) {
    const std::string key =
        section_.empty() ? std::string(name) : section_ + "." + std::string(name);
    if (name.empty()) fail("", "missing parameter name before '='");
    ParameterSpec* spec = find(key);
    if (!spec) fail(key, "unknown parameter (roadcross-build --print-config lists them all)");
    if (!seen_.insert(key).second) fail(key, "given twice");
    const std::optional<double> value = parse_number(value_text);
    if (!value) fail(key, "'" + std::string(value_text) + "' is not a number");
    if (*value < spec->min || *value > spec->max) {
      fail(key, format_number(*value) + " is out of range [" + format_number(spec->min) + ", " +
                    format_number(spec->max) + "]");
    }
    if (spec->integer && *value != std::floor(*value)) {
      fail(key, format_number(*value) + " is not a whole number");
    }
    *spec->value = *value;
  }

  ParameterSpec* find(const std::string& key) {
    for (ParameterSpec& spec : specs_) {
      if (spec.key() == key) return &spec;
    }
    return nullptr;
  }

  std::string name_;
  std::vector<ParameterSpec> specs_;
  std::set<std::string> sections_;
  std::set<std::string> seen_;
  std::string section_;
  std::size_t number_ = 0;
};

std::string range_text(const ParameterSpec& spec) {
  return std::string(spec.integer ? "whole number" : "number") + " in [" + format_number(spec.min) +
         ", " + format_number(spec.max) + "]";
}

}  // namespace

std::string format_parameter_file(const Parameters& parameters) {
  std::ostringstream out;
  out << "# roadcross-build parameters: every weight and threshold of the cost model.\n"
         "# Load with `roadcross-build --config FILE`; a --section.name flag overrides a value.\n"
         "# The format is both INI and TOML. docs/cost-model.md explains each value.\n";
  std::string section;
  for (const ParameterSpec& spec : parameters.specs()) {
    if (spec.section != section) {
      section = spec.section;
      out << "\n[" << section << "]\n";
    }
    out << "# " << spec.description << " (" << range_text(spec) << ")\n"
        << spec.name << " = " << format_number(*spec.value) << "\n";
  }
  return out.str();
}

void parse_parameter_text(std::string_view text, const std::string& name, Parameters& parameters) {
  TextParser parser(name, parameters);
  std::size_t number = 1;
  while (!text.empty()) {
    const std::size_t newline = text.find('\n');
    parser.line(text.substr(0, newline), number++);
    if (newline == std::string_view::npos) break;
    text.remove_prefix(newline + 1);
  }
}

void read_parameter_file(const std::string& path, Parameters& parameters) {
  // A parameter file is a few kB: a folder, a device (/dev/zero is endless) or a huge file is a
  // mistake, said before reading.
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(status)) {
    throw ParameterError(path + ": cannot open the parameter file (no such file)");
  }
  if (std::filesystem::is_directory(status)) {
    throw ParameterError(path + ": is a folder, not a parameter file");
  }
  if (!std::filesystem::is_regular_file(status)) {
    throw ParameterError(path + ": is not a regular file (a device, FIFO or socket)");
  }
  if (std::filesystem::file_size(path, ec) > kMaxParameterFileBytes) {
    throw ParameterError(path + ": larger than " + std::to_string(kMaxParameterFileBytes) +
                         " bytes; a parameter file is a few kB");
  }
  std::ifstream file(path, std::ios::binary);
  if (!file) throw ParameterError(path + ": cannot open the parameter file");
  std::string text(kMaxParameterFileBytes + 1, '\0');
  file.read(text.data(), static_cast<std::streamsize>(text.size()));
  if (file.bad()) throw ParameterError(path + ": cannot read the parameter file");
  text.resize(static_cast<std::size_t>(file.gcount()));
  if (text.size() > kMaxParameterFileBytes) {
    throw ParameterError(path + ": larger than " + std::to_string(kMaxParameterFileBytes) +
                         " bytes; a parameter file is a few kB");
  }
  parse_parameter_text(text, path, parameters);
}

}  // namespace roadcross::preprocess
