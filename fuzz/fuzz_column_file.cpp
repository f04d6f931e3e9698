// libFuzzer: the plain column-file parser on arbitrary bytes.
#include <cstdint>
#include <string_view>

#include "mlce/reader/column_file.hpp"
#include "mlce/reader/table.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  for (const auto& keep : {std::vector<std::size_t>{}, std::vector<std::size_t>{2, 1}})
    for (const bool text_columns : {false, true}) {
      try {
        mlce::reader::ColumnFileOptions o;
        o.keep = keep;
        o.text_columns = text_columns;
        const auto t = mlce::reader::parse_column_text(text, "fuzz.txt", o);
        t.require_numbers({0, 1, 2}, t.line_of(t.rows() - 1) / 2);
        t.require_numbers({1, 0});
      } catch (const mlce::reader::ReadError&) {
      }
    }
  return 0;
}
