// csv_rows: the rows of a CSV table made from its columns, for `pydrill atlas export --out
// X.csv`. pandas' to_csv spent 11 of a 250000-point export's 14 s turning floats into text
// (numpy's repr, then Python's csv writer); std::to_chars finds the same shortest digits in a
// tenth of that. The text is what pandas writes, byte for byte: floats as Python's repr lays
// them out, NaN as an empty cell, integers as integers.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "bindings.hpp"

namespace py = pybind11;

namespace pydrill::bindings {
namespace {

// x as Python's repr writes it: the shortest digits that read back as x, laid out fixed for
// decimal exponents -4 ... 15 ("0.0001", "1000000000000000.0", "1.5") and scientific
// otherwise ("1e-05", "1e+16", "1.2345e+100"); "nan", "inf", "-inf", "-0.0".
void append_repr(std::string& out, double x) {
  if (std::isnan(x)) {
    out += "nan";
    return;
  }
  if (std::isinf(x)) {
    out += x < 0 ? "-inf" : "inf";
    return;
  }
  char buf[40];
  // Scientific, shortest round trip: "-d.ddde-XX" — the digits and the exponent to lay out.
#if defined(__cpp_lib_to_chars) && !defined(PYDRILL_NO_FLOAT_TO_CHARS)
  auto [end, ec] = std::to_chars(buf, buf + sizeof buf, x, std::chars_format::scientific);
  if (ec != std::errc()) throw std::runtime_error("csv_rows: cannot format a float");
#else
  // A standard library without floating-point to_chars (libc++ before 17, macOS before 13.3):
  // the fewest digits that read back as x (17 always do, and more never fail where fewer
  // read back), found by bisection; several times slower.
  auto print = [&](int digits) { return std::snprintf(buf, sizeof buf, "%.*e", digits - 1, x); };
  int lo = 1, hi = 17;
  while (lo < hi) {
    const int mid = (lo + hi) / 2;
    print(mid);
    if (std::strtod(buf, nullptr) == x)
      hi = mid;
    else
      lo = mid + 1;
  }
  const char* end = buf + print(lo);
#endif
  const char* p = buf;
  if (*p == '-') {
    out += '-';
    ++p;
  }
  char digits[24];
  int n = 0;
  for (; p < end && *p != 'e'; ++p)
    if (*p != '.') digits[n++] = *p;
  // to_chars writes "e+XX" or "e-XX", not NUL-terminated
  const bool negative = p + 1 < end && p[1] == '-';
  int magnitude = 0;
  std::from_chars(p + 2, end, magnitude);
  const int exponent = negative ? -magnitude : magnitude;
  if (exponent < -4 || exponent >= 16) {
    out += digits[0];
    if (n > 1) {
      out += '.';
      out.append(digits + 1, n - 1);
    }
    out += exponent < 0 ? "e-" : "e+";
    const int e = exponent < 0 ? -exponent : exponent;
    if (e < 10) out += '0';
    out += std::to_string(e);
  } else if (exponent < 0) {
    out += "0.";
    out.append(static_cast<std::size_t>(-exponent - 1), '0');
    out.append(digits, n);
  } else {
    const int whole = exponent + 1;  // digits before the point
    if (n <= whole) {
      out.append(digits, n);
      out.append(static_cast<std::size_t>(whole - n), '0');
      out += ".0";
    } else {
      out.append(digits, whole);
      out += '.';
      out.append(digits + whole, n - whole);
    }
  }
}

void append_int(std::string& out, std::int64_t v) {
  char buf[24];
  auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, end);
}

enum class Kind { Float, Int, Count, Text };

struct Column {
  Kind kind;
  const double* reals = nullptr;     // Float, Count
  const std::int64_t* ints = nullptr;  // Int; Text: codes
  std::vector<std::string> labels;   // Text
  py::array keep;                    // owns the data while the GIL is released
};

Column column_of(const py::tuple& spec, py::ssize_t rows) {
  if (spec.size() != 2) throw std::invalid_argument("csv_rows: a column is (kind, values)");
  const auto kind = spec[0].cast<std::string>();
  Column c{};
  if (kind == "float" || kind == "count") {
    c.kind = kind == "float" ? Kind::Float : Kind::Count;
    c.keep = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(spec[1]);
    c.reals = static_cast<const double*>(c.keep.data());
  } else if (kind == "int") {
    c.kind = Kind::Int;
    c.keep = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(spec[1]);
    c.ints = static_cast<const std::int64_t*>(c.keep.data());
  } else if (kind == "text") {
    c.kind = Kind::Text;
    auto pair = spec[1].cast<py::tuple>();
    if (pair.size() != 2) throw std::invalid_argument("csv_rows: text is (codes, labels)");
    c.keep = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(pair[0]);
    c.ints = static_cast<const std::int64_t*>(c.keep.data());
    c.labels = pair[1].cast<std::vector<std::string>>();
    for (py::ssize_t i = 0; i < rows; ++i)  // checked here: the loop below trusts the codes
      if (c.ints[i] < -1 || c.ints[i] >= std::int64_t(c.labels.size()))
        throw std::invalid_argument("csv_rows: a text code has no label");
  } else {
    throw std::invalid_argument("csv_rows: kind must be float, int, count or text, got " + kind);
  }
  if (!c.keep || c.keep.ndim() != 1 || c.keep.shape(0) != rows)
    throw std::invalid_argument("csv_rows: every column must be 1-D with one value per row");
  return c;
}

py::bytes csv_rows(const py::list& columns, py::ssize_t rows) {
  if (rows < 0) throw std::invalid_argument("csv_rows: rows must be >= 0");
  std::vector<Column> cols;
  cols.reserve(columns.size());
  for (const auto& spec : columns) cols.push_back(column_of(spec.cast<py::tuple>(), rows));
  std::string out;
  {
    py::gil_scoped_release release;  // the other threads (a progress bar) go on meanwhile
    out.reserve(static_cast<std::size_t>(rows) * (cols.size() * 12 + 1));
    for (py::ssize_t i = 0; i < rows; ++i) {
      for (std::size_t j = 0; j < cols.size(); ++j) {
        if (j) out += ',';
        const Column& c = cols[j];
        switch (c.kind) {
          case Kind::Float:
            if (!std::isnan(c.reals[i])) append_repr(out, c.reals[i]);  // NaN: an empty cell
            break;
          case Kind::Count:  // whole numbers below 2^53 (an int64 cast beyond 2^63 is undefined)
            if (std::isnan(c.reals[i])) break;
            if (std::fabs(c.reals[i]) < 9.0e15)
              append_int(out, static_cast<std::int64_t>(c.reals[i]));
            else
              append_repr(out, c.reals[i]);
            break;
          case Kind::Int:
            append_int(out, c.ints[i]);
            break;
          case Kind::Text:
            if (c.ints[i] >= 0) out += c.labels[static_cast<std::size_t>(c.ints[i])];
            break;
        }
      }
      out += '\n';
    }
  }
  return py::bytes(out);
}

}  // namespace

void bind_table(py::module_& m) {
  m.def("csv_rows", &csv_rows, py::arg("columns"), py::arg("rows"),
        "The rows of a CSV table, as bytes: columns is a list of (kind, values), kind 'float' "
        "(float64; Python's repr, NaN empty), 'int' (int64), 'count' (float64 of whole "
        "numbers, NaN empty) or 'text' ((codes, labels): labels[code], -1 empty; labels "
        "already quoted as CSV needs).");
}

}  // namespace pydrill::bindings
