// A small JSON document builder for reports (metrics, summaries): ordered keys, numbers written
// with round-trip precision, NaN/Inf written as null.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace smap::core
{
class JsonValue
{
public:
    static JsonValue object();
    static JsonValue array();
    static JsonValue number(double d);
    static JsonValue integer(int64_t i);
    static JsonValue string(const std::string& s);
    static JsonValue boolean(bool b);

    /// Object members keep insertion order; returns *this for chaining.
    JsonValue& set(const std::string& key, JsonValue v);
    JsonValue& set(const std::string& key, double v) { return set(key, number(v)); }
    JsonValue& set(const std::string& key, int v) { return set(key, integer(v)); }
    JsonValue& set(const std::string& key, int64_t v) { return set(key, integer(v)); }
    JsonValue& set(const std::string& key, uint64_t v)
    {
        return set(key, integer(static_cast<int64_t>(v)));
    }
    JsonValue& set(const std::string& key, const std::string& v) { return set(key, string(v)); }
    JsonValue& set(const std::string& key, const char* v) { return set(key, string(v)); }
    JsonValue& set(const std::string& key, bool v) { return set(key, boolean(v)); }
    JsonValue& push(JsonValue v);
    /// An object's member (nullptr when it has none of that name).
    JsonValue* find(const std::string& key);
    /// Removes an object's member, if present; returns *this for chaining.
    JsonValue& erase(const std::string& key);
    /// An array's items.
    size_t size() const { return items_.size(); }
    JsonValue& at(size_t i) { return items_.at(i); }

    std::string dump(int indent = 2) const;

private:
    enum class Kind
    {
        Object,
        Array,
        Number,
        Integer,
        String,
        Boolean
    };
    void dumpTo(std::string& out, int indent, int level) const;

    Kind kind_ = Kind::Object;
    double number_ = 0.0;
    int64_t integer_ = 0;
    bool boolean_ = false;
    std::string string_;
    std::vector<std::pair<std::string, JsonValue>> members_;
    std::vector<JsonValue> items_;
};

std::string jsonEscape(const std::string& s);
}  // namespace smap::core
