#!/usr/bin/env python3
"""Random draws are sequenced: no two of them are unsequenced parts of one expression.

The order in which a call's arguments are evaluated is unspecified: GCC takes them right to left on
x86-64 and left to right on aarch64, so f(rng.Uniform(..), rng.Uniform(..)) gives the two builds
different random bodies, and a threshold measured on one can fail on the other. The same holds for
the operands of an overloaded operator (Eigen's s * v is a call), and C++ leaves the operands of
the built-in ones unsequenced too. So this check reports, as file:line, every call whose argument
list has two or more arguments that draw, and every expression with two or more operands that draw,
where drawing means naming a generator (rng, gen, engine, ...) or calling Rng's own Uniform,
Normal, Rotation, UniformVector or RandomPose (or the study's uniform). What C++ sequences is
allowed: separate statements, braced lists (left to right), the comma operator and declarator
lists, &&, ||, ?:, <<, >> and assignments, a callee's object before its arguments, a lambda's body
(it runs later). Fix: draw into named locals first, one per statement, in the order the x86-64
build drew them (tests/test_support.hpp, class Rng).
Usage: check_draw_order.py SOURCE_DIR
"""
import os
import re
import sys

DIRS = ["src", "include", "tests", "tools", "bench", "examples", "python"]
EXTENSIONS = (".cpp", ".hpp", ".h", ".cc")
GENERATOR = re.compile(r"\b(rng|gen|gen_|engine|random)\b")
OWN_DRAW = re.compile(r"(?<![.>:\w])(Uniform|Normal|Rotation|UniformVector|RandomPose|uniform3?)\s*(<[^<>()]*>)?\s*\(")
DECLARATION = re.compile(r"\b(Rng|mt19937(_64)?)\s*[&*]")  # a parameter declared, not a draw
CONTROL = {"if", "for", "while", "switch", "catch"}
NOT_CALLS = CONTROL | {"return", "sizeof", "decltype", "alignof", "noexcept", "static_assert", "defined", "throw"}
# Sequencing operators at one level of an expression, longest first. '=' only as an assignment.
SEQUENCING = re.compile(r"<<=|>>=|\+=|-=|\*=|/=|%=|&=|\|=|\^=|<<|>>|&&|\|\||(?<![=!<>])=(?!=)|\?|(?<!:):(?!:)|,|;")
OPERATOR = set("+-*/%<>&|^!~=")


def strip(src):
    """src with comments and the insides of string and character literals blanked, lines kept."""
    out, i, n = [], 0, len(src)
    while i < n:
        if src.startswith("//", i):
            j = src.find("\n", i)
            j = n if j < 0 else j
        elif src.startswith("/*", i):
            j = src.find("*/", i + 2)
            j = n if j < 0 else j + 2
        elif src.startswith('R"', i) and (i == 0 or not (src[i - 1].isalnum() or src[i - 1] == "_")):
            m = re.match(r'R"([^(\s]*)\(', src[i:])
            if not m:
                out.append(src[i])
                i += 1
                continue
            end = src.find(")" + m.group(1) + '"', i)
            j = n if end < 0 else end + len(m.group(1)) + 2
        elif src[i] in "\"'" and not (src[i] == "'" and i > 0 and src[i - 1].isalnum()):  # not 1'000
            j = i + 1
            while j < n and src[j] != src[i] and src[j] != "\n":
                j += 2 if src[j] == "\\" else 1
            j += 1
        else:
            out.append(src[i])
            i += 1
            continue
        out.append(re.sub(r"[^\n]", " ", src[i:j]))
        i = j
    return "".join(out)


class Checker:
    def __init__(self, text):
        self.text = text
        self.close = {}  # index of each bracket -> index of its partner
        stack = []
        for i, c in enumerate(text):
            if c in "([{":
                stack.append(i)
            elif c in ")]}" and stack:
                self.close[stack.pop()] = i
        self.found = set()

    def split(self, lo, hi, separators):
        """text[lo:hi] cut at the matches of `separators` outside brackets."""
        parts, start, i = [], lo, lo
        while i < hi:
            if self.text[i] in "([{":
                i = self.close.get(i, hi) + 1
                continue
            m = separators.match(self.text, i, hi)
            if m:
                parts.append((start, i))
                start = i = m.end()
            else:
                i += 1
        parts.append((start, hi))
        return parts

    def expression(self, lo, hi):
        """Reports unsequenced draws in text[lo:hi]; returns whether it draws at all."""
        draws = False
        for a, b in self.split(lo, hi, SEQUENCING):
            drawing_operands = self.operands(a, b)
            if drawing_operands >= 2:
                self.found.add(a + len(self.text[a:b]) - len(self.text[a:b].lstrip()))
            draws = draws or drawing_operands > 0
        return draws

    def operands(self, lo, hi):
        """How many operands of the operator-separated text[lo:hi] draw."""
        text, count, draws, empty, i = self.text, 0, False, True, lo
        while i < hi:
            c = text[i]
            if c in OPERATOR and not text.startswith("->", i) and not (c == "<" and self.template(i, hi)):
                count += draws
                draws, empty = False, True
                i += 1
                continue
            if c == "[" and empty:  # a lambda: its body runs later, as statements of its own
                j = self.close.get(i, hi) + 1
                while j < hi and text[j] not in "{;,)":
                    j = self.close.get(j, j) + 1 if text[j] == "(" else j + 1
                if j < hi and text[j] == "{":
                    self.statements(j + 1, self.close.get(j, hi))
                    i = self.close.get(j, hi) + 1
                else:
                    i = j
                empty = False
                continue
            if c in "([{":
                end = self.close.get(i, hi)
                before = text[lo:i].rstrip()
                word = re.search(r"(\w+)$", before)
                if c == "(" and before and not empty and (word or before[-1] in ">)]") and not (
                        word and word.group(1) in NOT_CALLS):
                    drawing_arguments = sum(
                        1 for a, b in self.split(i + 1, end, re.compile(","))
                        if not DECLARATION.search(text[a:b]) and self.expression(a, b))
                    if drawing_arguments >= 2:
                        self.found.add(i)
                    draws = draws or drawing_arguments > 0
                elif c == "{":  # a braced list: its elements are sequenced
                    draws = any([self.expression(a, b) for a, b in self.split(i + 1, end, re.compile(","))]) or draws
                else:  # a parenthesized expression or a subscript (sequenced after what it indexes)
                    draws = self.expression(i + 1, end) or draws
                empty = False
                i = end + 1
                continue
            m = GENERATOR.match(text, i) or OWN_DRAW.match(text, i)
            if m and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
                draws, empty = True, False
                i = m.end() if m.re is GENERATOR else text.index("(", i)
                continue
            if not c.isspace():
                empty = False
            i += 1
        return count + draws

    def template(self, i, hi):
        """Whether the '<' at i opens template arguments (a name before it, a matching '>' soon after)."""
        before = self.text[:i].rstrip()
        if not re.search(r"[A-Za-z_]\w*$", before) or re.search(r"\b(operator|return)$", before):
            return False
        m = re.match(r"<[\w\s:,*&<>]*?>(?!>)", self.text[i:hi])
        return m is not None and self.text[i + 1:i + 2] != "<"

    def statements(self, lo, hi):
        """Checks the statements of a block text[lo:hi] (split at ; and at braces outside brackets)."""
        text, start, i = self.text, lo, lo
        while i < hi:
            c = text[i]
            if c in "{};":
                self.statement(start, i)
                if c == "{":
                    end = self.close.get(i, hi)
                    self.statements(i + 1, end)
                    i = start = end + 1
                    continue
                start = i + 1
            elif c in "([":
                i = self.close.get(i, hi)
            i += 1
        self.statement(start, hi)

    def statement(self, lo, hi):
        # A control statement's condition is a full expression of its own.
        m = re.match(r"\s*(?:else\s+)?(\w+)\s*\(", self.text[lo:hi])
        if m and m.group(1) in CONTROL:
            open_index = lo + m.end() - 1
            end = self.close.get(open_index, hi)
            for a, b in self.split(open_index + 1, end, re.compile(";")):
                self.expression(a, b)
            lo = end + 1
        self.expression(lo, hi)


def check(path):
    text = strip(open(path, encoding="utf-8", errors="replace").read())
    checker = Checker(text)
    checker.statements(0, len(text))
    return sorted({text.count("\n", 0, i) + 1 for i in checker.found})


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else "."
    bad = 0
    for d in DIRS:
        for dirpath, dirnames, filenames in os.walk(os.path.join(root, d)):
            dirnames.sort()
            for name in sorted(filenames):
                if name.endswith(EXTENSIONS):
                    path = os.path.join(dirpath, name)
                    for line in check(path):
                        print(f"{os.path.relpath(path, root)}:{line}: random draws not sequenced")
                        bad += 1
    if bad:
        print(f"{bad} expression(s) draw random numbers in an unspecified order, which differs between x86-64 and "
              "aarch64: draw into locals first, one per statement (tests/test_support.hpp, class Rng)")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
