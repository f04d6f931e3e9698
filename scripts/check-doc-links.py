#!/usr/bin/env python3
# Every relative Markdown link of README.md and docs/*.md names a file that exists and, with #anchor, a heading
# of that file (GitHub anchors: lowercased, punctuation dropped, spaces as hyphens). Exit 1 and one line per bad link.
#   scripts/check-doc-links.py
import re, os, sys
def anchors(path):
    out=set(); incode=False
    for l in open(path):
        if l.startswith('```'): incode=not incode; continue
        if incode: continue
        m=re.match(r'^(#+) (.*)',l)
        if m:
            t=m.group(2).strip().lower()
            t=re.sub(r'[^\w\- ]','',t)  # keeps unicode letters, digits, _, -, space
            out.add(t.replace(' ','-'))
    return out
bad=0
os.chdir(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
files=['README.md']+['docs/'+f for f in os.listdir('docs') if f.endswith('.md')]
for f in files:
    text=open(f).read()
    for m in re.finditer(r'\]\(([^)\s]+)\)',text):
        t=m.group(1)
        if re.match(r'^[a-z]+://',t): continue
        path,_,anc=t.partition('#')
        target=os.path.normpath(os.path.join(os.path.dirname(f),path)) if path else f
        if not os.path.exists(target): print(f,'missing file',t); bad+=1; continue
        if anc and target.endswith('.md') and anc not in anchors(target): print(f,'dangling',t); bad+=1
print(f"{bad} bad links") if bad else None
sys.exit(1 if bad else 0)
