// Numbers for people, as the build's progress line and summaries print them.
#pragma once

#include <string>

namespace roadcross::preprocess {

/// A count for people: whole number, digits grouped by thousands ("95,620"); "-" when not finite.
std::string format_count(double value);
/// A quantity for people (rates, sizes): from 100 up as format_count, below with three
/// significant digits ("42.5", "0.123"); never in exponent form.
std::string format_quantity(double value);

}  // namespace roadcross::preprocess
