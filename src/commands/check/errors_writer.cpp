#include "commands/check/errors_writer.hpp"

#include <fmt/format.h>

namespace eulervop::app {

errors_writer::errors_writer(const std::optional<std::string>& path) {
  if (path) file_ = std::make_unique<atomic_file>(*path);
}

void errors_writer::header(const std::string& time_name, bool certified, bool attitude) {
  if (file_)
    buffer_ += fmt::format("line,{},error,bar{}{}\n", time_name, certified ? ",radius" : "",
                           attitude ? ",attitude_error" : "");
}

void errors_writer::row(std::size_t line, const std::string& time, double error, std::optional<double> bar,
                        const std::optional<decimal>& radius, const std::string* attitude_error) {
  if (!file_) return;
  buffer_ += fmt::format("{},{},{},", line, time, error);
  if (bar) buffer_ += fmt::format("{}", *bar);
  if (radius) buffer_ += "," + radius->text;
  if (attitude_error) buffer_ += "," + *attitude_error;
  buffer_ += "\n";
  if (buffer_.size() > (1u << 16)) flush();
}

void errors_writer::commit() {
  if (!file_) return;
  flush();
  file_->commit();
}

void errors_writer::flush() {
  file_->write(buffer_);
  buffer_.clear();
}

}  // namespace eulervop::app
