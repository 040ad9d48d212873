// A table of an options struct's fields, each declared once: its name, type,
// help, allowed values and range, bound to the field. The front ends (the
// report's description, the command-line flags, the Python keywords, the
// sweep files, the editor's panels) read the table instead of restating the
// fields, and the struct's Check reads its ranges, so a new option is one row
// beside its struct field, in the struct's header:
//
//   struct Foo { double weight = 1.0; Mode mode = Mode::kFast; Inner inner; };
//
//   template <typename Table>  // only foo.cc, which builds the table, compiles the rows
//   void DeclareFooRows(Table& t) {
//     t.Double("weight", &Foo::weight, "w of Eq. 3.").AtLeast(0, "a finite weight >= 0");
//     t.Enum("mode", &Foo::mode, ModeNames(), "How it runs.");
//     t.Embed("inner", &Foo::inner, InnerTable());   // rows "inner.<name>"
//   }
//   const OptionTable<Foo>& FooTable();
//
// and in foo.cc, once:
//
//   const OptionTable<Foo>& FooTable() {
//     static const OptionTable<Foo>& table =
//         MakeOptionTable<Foo>([](auto& t) { DeclareFooRows(t); });
//     return table;
//   }
//   FooTable().Describe(foo);                 // {("weight", "1"), ("mode", "fast"), ...}
//   FooTable().Set("weight", "2", &foo, &e);  // e: "weight=-1: expected a finite weight >= 0"
//
// Enum names come from one EnumNames<E> per enum: Name(value), Parse(name,
// &value), and the names for error messages.

#ifndef MSDEFORM_CORE_OPTION_TABLE_H_
#define MSDEFORM_CORE_OPTION_TABLE_H_

#include <cstdint>
#include <functional>
#include <initializer_list>
#include <limits>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace msdeform {

// "%.17g": a double as reports print it, exact on reading back.
std::string OptionNumberText(double value);
// The shortest of %.15g, %.16g, %.17g that reads back exactly ("0.1"), for
// messages and flags.
std::string OptionShortNumberText(double value);
// Whole-string parses; false for trailing text, an empty string or overflow.
bool ParseOptionDouble(const std::string& text, double* value);
bool ParseOptionBool(const std::string& text, bool* value);  // true/false, 1/0
bool ParseOptionInteger(const std::string& text, long long* value);
bool ParseOptionUnsigned(const std::string& text, unsigned long long* value);
// "a, b or c".
std::string JoinChoices(const std::vector<std::string>& names);
// The name of `names` nearest to `name` (Levenshtein distance) when it is
// within max(2, |name| / 3) edits, else "": what "did you mean" offers for a
// mistyped flag (apps/flags) or keyword (Python).
std::string NearestName(const std::string& name, const std::vector<std::string>& names);

// The names of an enum's values: one {value, "name"} per value.
template <typename E>
class EnumNames {
 public:
  EnumNames(std::initializer_list<std::pair<E, const char*>> entries) {
    for (const auto& [value, name] : entries) entries_.emplace_back(value, name);
  }
  // From an existing Name function, for the values listed.
  template <typename NameFunction>
  static EnumNames FromFunction(const std::vector<E>& values, NameFunction name) {
    EnumNames names({});
    for (E value : values) names.entries_.emplace_back(value, std::string(name(value)));
    return names;
  }

  const char* Name(E value) const {
    for (const auto& entry : entries_) {
      if (entry.first == value) return entry.second.c_str();
    }
    return "unknown";
  }
  bool Parse(const std::string& name, E* value) const {
    for (const auto& entry : entries_) {
      if (entry.second == name) {
        *value = entry.first;
        return true;
      }
    }
    return false;
  }
  std::vector<E> values() const {
    std::vector<E> result;
    for (const auto& entry : entries_) result.push_back(entry.first);
    return result;
  }
  std::vector<std::string> names() const {
    std::vector<std::string> result;
    for (const auto& entry : entries_) result.push_back(entry.second);
    return result;
  }
  // "a, b or c", for "expected a, b or c".
  std::string Expected() const { return JoinChoices(names()); }

 private:
  std::vector<std::pair<E, std::string>> entries_;
};

enum class OptionType { kBool, kInt, kDouble, kString, kEnum };
const char* OptionTypeName(OptionType type);  // "bool", "int", "double", "string", "enum"

// One field of T: its name ("lattice.cell_width" where embedded), other
// spellings the front ends accept (legacy command-line names), the
// command-line topic ("" when it is not a flag), help, the enum's names, a
// range, and the field's value as text and set from text.
template <typename T>
struct OptionRow {
  std::string name;
  OptionType type = OptionType::kDouble;
  std::string help;
  std::vector<std::string> aliases;
  std::string topic;
  std::vector<std::string> choices;
  // Words before the enum's names in an error ("one this Ceres has: ").
  std::string choice_words;
  // Range of a number: lo <(=) value <(=) hi and finite; `expected` words it.
  bool has_range = false;
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false, hi_open = false;
  std::string expected;
  std::function<std::string(const T&)> get;
  // Parses `text` into the field; false with what is wrong ("expected ...").
  std::function<bool(const std::string& text, T*, std::string* what)> parse;

  // Modifiers, chained after a row is declared.
  OptionRow& Range(double low, double high, const std::string& words, bool high_open = false) {
    has_range = true, lo = low, hi = high, hi_open = high_open, lo_open = false, expected = words;
    return *this;
  }
  OptionRow& AtLeast(double low, const std::string& words) {
    return Range(low, std::numeric_limits<double>::infinity(), words, true);
  }
  OptionRow& Above(double low, const std::string& words) {
    Range(low, std::numeric_limits<double>::infinity(), words, true);
    lo_open = true;
    return *this;
  }
  OptionRow& Alias(const std::string& spelling) {
    aliases.push_back(spelling);
    return *this;
  }
  OptionRow& ChoiceWords(const std::string& words) {
    choice_words = words;
    return *this;
  }
  OptionRow& Flag(const std::string& flag_topic) {
    topic = flag_topic;
    return *this;
  }
  bool InRange(double value) const {
    if (!has_range) return true;
    if (!(value == value) || value < lo || value > hi) return false;
    if (lo_open && value == lo) return false;
    if (hi_open && value == hi) return false;  // also: an open infinite bound means finite
    return true;
  }
};

template <typename T>
class OptionTable {
 public:
  using Row = OptionRow<T>;

  Row& Bool(const std::string& name, bool T::*member, const std::string& help) {
    Row& row = Add(name, OptionType::kBool, help);
    row.get = [member](const T& t) { return std::string(t.*member ? "true" : "false"); };
    row.parse = [member](const std::string& text, T* t, std::string* what) {
      if (ParseOptionBool(text, &(t->*member))) return true;
      *what = "expected true or false";
      return false;
    };
    return row;
  }

  // int, long long, std::uint64_t.
  template <typename I>
  Row& Int(const std::string& name, I T::*member, const std::string& help) {
    static_assert(std::is_integral<I>::value, "an integer field");
    Row& row = Add(name, OptionType::kInt, help);
    row.get = [member](const T& t) { return std::to_string(t.*member); };
    row.parse = [member](const std::string& text, T* t, std::string* what) {
      bool ok;
      I value{};
      if (std::is_unsigned<I>::value) {
        unsigned long long v = 0;
        ok = ParseOptionUnsigned(text, &v) && v <= std::numeric_limits<I>::max();
        value = static_cast<I>(v);
      } else {
        long long v = 0;
        ok = ParseOptionInteger(text, &v) && v >= static_cast<long long>(std::numeric_limits<I>::min()) &&
             v <= static_cast<long long>(std::numeric_limits<I>::max());
        value = static_cast<I>(v);
      }
      if (!ok) {
        *what = "expected an integer in " + std::to_string(std::numeric_limits<I>::min()) + ".." +
                std::to_string(std::numeric_limits<I>::max());
        return false;
      }
      t->*member = value;
      return true;
    };
    return row;
  }

  Row& Double(const std::string& name, double T::*member, const std::string& help) {
    Row& row = Add(name, OptionType::kDouble, help);
    row.get = [member](const T& t) { return OptionNumberText(t.*member); };
    row.parse = [member](const std::string& text, T* t, std::string* what) {
      if (ParseOptionDouble(text, &(t->*member))) return true;
      *what = "expected a number";
      return false;
    };
    return row;
  }

  template <typename E>
  Row& Enum(const std::string& name, E T::*member, const EnumNames<E>& names,
            const std::string& help) {
    Row& row = Add(name, OptionType::kEnum, help);
    row.choices = names.names();
    row.get = [member, names](const T& t) { return std::string(names.Name(t.*member)); };
    row.parse = [member, names](const std::string& text, T* t, std::string* what) {
      if (names.Parse(text, &(t->*member))) return true;
      *what = "expected " + names.Expected();
      return false;
    };
    return row;
  }

  // Every row of `sub` as "<prefix>.<name>" (as "<name>" for an empty
  // prefix: a larger struct that keeps the embedded one's vocabulary, e.g.
  // a method's options holding DeformerOptions), bound to this->*member; a
  // sub-row's aliases and topic are kept (they name the flag, not the field).
  template <typename S>
  void Embed(const std::string& prefix, S T::*member, const OptionTable<S>& sub) {
    Embed<S>(
        prefix, [member](const T& t) -> const S& { return t.*member; },
        [member](T* t) { return &(t->*member); }, sub);
  }

  // The same for an S that T holds other than as a member (a method's options
  // kept by name, methods/method_options.h): `get` reads it, `get_mutable`
  // gives it to write.
  template <typename S>
  void Embed(const std::string& prefix, std::function<const S&(const T&)> get_sub,
             std::function<S*(T*)> get_mutable_sub, const OptionTable<S>& sub) {
    for (const OptionRow<S>& s : sub.rows()) {
      Row row;
      row.name = prefix.empty() ? s.name : prefix + "." + s.name;
      row.type = s.type, row.help = s.help, row.aliases = s.aliases, row.topic = s.topic;
      row.choices = s.choices, row.choice_words = s.choice_words, row.has_range = s.has_range, row.lo = s.lo, row.hi = s.hi;
      row.lo_open = s.lo_open, row.hi_open = s.hi_open, row.expected = s.expected;
      auto get = s.get;
      auto parse = s.parse;
      row.get = [get_sub, get](const T& t) { return get(get_sub(t)); };
      row.parse = [get_mutable_sub, parse](const std::string& text, T* t, std::string* what) {
        return parse(text, get_mutable_sub(t), what);
      };
      rows_.push_back(std::move(row));
    }
  }

  // The last row declared, to change it (an embedded row's alias or topic).
  Row& Last() { return rows_.back(); }
  Row* Mutable(const std::string& name) {
    for (Row& row : rows_) {
      if (row.name == name) return &row;
    }
    return nullptr;
  }

  const std::vector<Row>& rows() const { return rows_; }

  // The row named `name` or spelled so by an alias; nullptr if none.
  const Row* Find(const std::string& name) const {
    for (const Row& row : rows_) {
      if (row.name == name) return &row;
    }
    for (const Row& row : rows_) {
      for (const std::string& alias : row.aliases) {
        if (alias == name) return &row;
      }
    }
    return nullptr;
  }

  // Every field as (name, value) in declaration order, numbers %.17g.
  std::vector<std::pair<std::string, std::string>> Describe(const T& options) const {
    std::vector<std::pair<std::string, std::string>> fields;
    for (const Row& row : rows_) fields.emplace_back(row.name, row.get(options));
    return fields;
  }

  // Sets the field named (or aliased) `name` from `text` and checks its
  // range; on failure *options is unchanged and *error is one line,
  // "<shown>=<text>: expected ..." (`shown` defaults to the name as given).
  bool Set(const std::string& name, const std::string& text, T* options, std::string* error,
           const std::string& shown = "") const {
    const std::string label = shown.empty() ? name : shown;
    const Row* row = Find(name);
    if (row == nullptr) {
      *error = label + ": not an option (the options are " + NameList() + ")";
      return false;
    }
    T candidate = *options;
    std::string what;
    if (!row->parse(text, &candidate, &what)) {
      if (row->type == OptionType::kEnum) {
        what = "expected " + row->choice_words + JoinChoices(row->choices);
      }
      *error = label + "=" + text + ": " + what;
      return false;
    }
    if (!InRange(*row, candidate, &what)) {
      *error = label + "=" + text + ": " + what;
      return false;
    }
    *options = candidate;
    return true;
  }

  // Every number within its row's range; else "<name>=<value>: expected ...".
  bool CheckRanges(const T& options, std::string* error) const {
    for (const Row& row : rows_) {
      std::string what;
      if (!InRange(row, options, &what)) {
        *error = row.name + "=" + row.get(options) + ": " + what;
        return false;
      }
    }
    return true;
  }

  std::string NameList() const {
    std::string names;
    for (const Row& row : rows_) names += (names.empty() ? "" : ", ") + row.name;
    return names;
  }

 private:
  Row& Add(const std::string& name, OptionType type, const std::string& help) {
    Row row;
    row.name = name;
    row.type = type;
    row.help = help;
    rows_.push_back(std::move(row));
    return rows_.back();
  }

  static bool InRange(const Row& row, const T& options, std::string* what) {
    if (!row.has_range) return true;
    double value = 0;
    if (!ParseOptionDouble(row.get(options), &value) || !row.InRange(value)) {
      *what = "expected " + row.expected;
      return false;
    }
    return true;
  }

  std::vector<Row> rows_;
};

// The largest int, as a row's upper bound (.Range(1, kOptionIntMax, ...)).
inline constexpr double kOptionIntMax = std::numeric_limits<int>::max();

// The table `declare(table)` fills, made once and never destroyed (a table
// outlives every static that reads it): the body of FooTable() above.
template <typename T, typename Declare>
const OptionTable<T>& MakeOptionTable(Declare declare) {
  auto* table = new OptionTable<T>();
  declare(*table);
  return *table;
}

}  // namespace msdeform

#endif  // MSDEFORM_CORE_OPTION_TABLE_H_
