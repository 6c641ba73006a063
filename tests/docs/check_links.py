#!/usr/bin/env python3
"""Every relative link and anchor in README.md and docs/ resolves.

Usage: check_links.py SOURCE_DIR. Checks [text](target) and <img src="target"> in each Markdown
file: the file or folder named must exist in the tree, and a #anchor must be a heading of the
target page (GitHub's rule: lower case, punctuation dropped, spaces to hyphens, repeats -1, -2).
Links to other sites (http:, https:, mailto:) are not followed. Exit 1 naming each broken link.
"""
import os
import re
import sys

LINK = re.compile(r'!?\[(?:[^\]\[]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+"[^"]*")?\s*\)')
IMG = re.compile(r'<img[^>]*\ssrc="([^"]+)"')
HEADING = re.compile(r'^(#{1,6})\s+(.*?)\s*#*\s*$')
FENCE = re.compile(r'^\s*(```|~~~)')


def slug(text):
    text = re.sub(r'`([^`]*)`', r'\1', text)
    text = re.sub(r'\[([^\]]*)\]\([^)]*\)', r'\1', text)
    text = text.strip().lower()
    text = re.sub(r'[^\w\- ]', '', text)
    return text.replace(' ', '-')


def anchors(path, cache={}):
    if path not in cache:
        seen, found, fenced = {}, set(), False
        with open(path, encoding='utf-8') as f:
            for line in f:
                if FENCE.match(line):
                    fenced = not fenced
                    continue
                m = None if fenced else HEADING.match(line)
                if m:
                    s = slug(m.group(2))
                    n = seen.get(s, 0)
                    seen[s] = n + 1
                    found.add(s if n == 0 else f'{s}-{n}')
                for a in re.findall(r'<a\s+(?:name|id)="([^"]+)"', line):
                    found.add(a)
        cache[path] = found
    return cache[path]


def links(path):
    fenced = False
    with open(path, encoding='utf-8') as f:
        for number, line in enumerate(f, 1):
            if FENCE.match(line):
                fenced = not fenced
                continue
            if fenced:
                continue
            stripped = re.sub(r'`[^`]*`', '', line)
            for m in LINK.finditer(stripped):
                yield number, m.group(1)
            for m in IMG.finditer(stripped):
                yield number, m.group(1)


def main():
    if len(sys.argv) != 2:
        print('usage: check_links.py SOURCE_DIR', file=sys.stderr)
        return 2
    root = os.path.abspath(sys.argv[1])
    pages = [os.path.join(root, 'README.md')]
    for d, _, files in os.walk(os.path.join(root, 'docs')):
        pages += [os.path.join(d, f) for f in sorted(files) if f.endswith('.md')]
    broken, count = [], 0
    for page in pages:
        for number, target in links(page):
            if re.match(r'^[a-z][a-z0-9+.-]*:', target):
                continue
            count += 1
            where = f'{os.path.relpath(page, root)}:{number}'
            file_part, _, anchor = target.partition('#')
            dest = page if not file_part else os.path.normpath(os.path.join(os.path.dirname(page), file_part))
            if not dest.startswith(root):
                broken.append(f'{where}: {target} leaves the project')
            elif not os.path.exists(dest):
                broken.append(f'{where}: {target}: no such file')
            elif anchor and dest.endswith('.md') and anchor not in anchors(dest):
                broken.append(f'{where}: {target}: no heading #{anchor} in {os.path.relpath(dest, root)}')
    for b in broken:
        print(b)
    print(f'check_links: {len(pages)} pages, {count} relative links, {len(broken)} broken')
    return 1 if broken else 0


if __name__ == '__main__':
    sys.exit(main())
