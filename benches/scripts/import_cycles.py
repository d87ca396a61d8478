#!/usr/bin/env python3
"""File-level import cycles inside each crate of the workspace.

Reads every `crate::` path (and `super::` in module folders) outside comments and test
modules, maps it to the file of the module it names, and prints each strongly connected
group of files with the imports that close it. Prints nothing and exits with 0 when there is no cycle, else 1.
Run from the workspace root: `python3 benches/scripts/import_cycles.py`.
"""
import glob
import os
import re
import sys

found = False
for crate in sorted(glob.glob('crates/*/src')+glob.glob('apps/*/src')+glob.glob('tests/src')):
    mods={}
    files=glob.glob(crate+'/**/*.rs',recursive=True)
    for f in files:
        rel=os.path.relpath(f,crate)[:-3].replace('/mod','').replace('/','::')
        if rel in('lib','main') or rel.startswith('bin'): continue
        code='\n'.join(l for l in open(f).read().split('\n') if not l.strip().startswith('//'))
        # strip test module
        if '#[cfg(test)]' in code: code=code[:code.index('#[cfg(test)]')]
        deps={}
        # crate:: paths, including within use braces
        for m in re.finditer(r'use crate::\{([^;]*)\};',code,re.S):
            for part in re.split(r',\s*(?![^{]*\})',m.group(1)):
                path=part.strip().split('::')
                for k in range(len(path),0,-1):
                    if os.path.exists(os.path.join(crate,*path[:k])+'.rs') or os.path.exists(os.path.join(crate,*path[:k],'mod.rs')):
                        deps.setdefault('::'.join(path[:k]),'use');break
        for m in re.finditer(r'crate::([a-z_]+(?:::[a-z_]+)*)',code):
            path=m.group(1).split('::')
            for k in range(len(path),0,-1):
                if os.path.exists(os.path.join(crate,*path[:k])+'.rs') or os.path.exists(os.path.join(crate,*path[:k],'mod.rs')):
                    deps.setdefault('::'.join(path[:k]),m.group(0));break
        # super:: within a module dir
        for m in re.finditer(r'super::([a-z_]+)',code):
            parent=rel.rsplit('::',1)[0] if '::' in rel else ''
            cand=(parent+'::' if parent else '')+m.group(1)
            p=cand.split('::')
            if os.path.exists(os.path.join(crate,*p)+'.rs') or os.path.exists(os.path.join(crate,*p,'mod.rs')):
                deps.setdefault(cand,m.group(0))
        deps={d:v for d,v in deps.items() if d!=rel and not rel.startswith(d+'::') and not d.startswith(rel+'::')}
        mods[rel]=deps
    idx={};low={};st=[];on=set();sccs=[];c=[0]
    sys.setrecursionlimit(10000)
    def sc(v):
        idx[v]=low[v]=c[0];c[0]+=1;st.append(v);on.add(v)
        for w in mods.get(v,{}):
            if w not in mods: continue
            if w not in idx: sc(w);low[v]=min(low[v],low[w])
            elif w in on: low[v]=min(low[v],idx[w])
        if low[v]==idx[v]:
            comp=[]
            while True:
                w=st.pop();on.discard(w);comp.append(w)
                if w==v:break
            if len(comp)>1: sccs.append(comp)
    for v in mods:
        if v not in idx: sc(v)
    for comp in sccs:
        found = True
        print(crate, comp)
        for a in comp:
            for b,u in mods[a].items():
                if b in comp: print('   ',a,'->',b,'(',u,')')

sys.exit(1 if found else 0)
