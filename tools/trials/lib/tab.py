"""Tiny helpers to read/modify/write mtwin CSV tables with a '# key = value' preamble."""
import csv, io, os


class Table:
    def __init__(self, path):
        pre, rest = [], []
        with open(path) as f:
            lines = f.read().splitlines()
        i = 0
        while i < len(lines) and lines[i].startswith('#'):
            pre.append(lines[i]); i += 1
        self.pre = pre
        self.header = lines[i].split(',')
        self.rows = [l.split(',') for l in lines[i + 1:] if l and not l.startswith('#')]

    def col(self, name):
        return self.header.index(name)

    def map(self, name, fn):
        j = self.col(name)
        for r in self.rows:
            r[j] = fn(r[j])
        return self

    def fmap(self, name, fn, fmt='%.6f'):
        return self.map(name, lambda s: s if s.strip() == '' else fmt % fn(float(s)))

    def rename(self, old, new):
        self.header[self.col(old)] = new
        return self

    def swap_cols(self, a, b):
        ia, ib = self.col(a), self.col(b)
        self.header[ia], self.header[ib] = b, a
        return self

    def drop(self, name):
        j = self.col(name)
        self.header.pop(j)
        for r in self.rows:
            r.pop(j)
        return self

    def set_pre(self, key, value):
        out, found = [], False
        for l in self.pre:
            if l.startswith('# ' + key + ' ='):
                out.append('# %s = %s' % (key, value)); found = True
            else:
                out.append(l)
        if not found:
            out.append('# %s = %s' % (key, value))
        self.pre = out
        return self

    def del_pre(self, key=None):
        if key is None:
            self.pre = []
        else:
            self.pre = [l for l in self.pre if not l.startswith('# ' + key + ' =')]
        return self

    def write(self, path):
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, 'w') as f:
            for l in self.pre:
                f.write(l + '\n')
            f.write(','.join(self.header) + '\n')
            for r in self.rows:
                f.write(','.join(r) + '\n')
        return path
