"""Per file of a directory of results files (NAME-rN.h5 for rounds of one variant): mean per round, median, the mean of frames whose op built ahead ("refit-ahead"), and the median over passes of each pass p95 over its median. Usage: /usr/bin/python3 bench/ahead_frames_report.py DIR"""
import h5py, sys, glob, os, numpy as np, collections
d=sys.argv[1]
rows=collections.defaultdict(list)
for fn in sorted(glob.glob(d+'/*.h5')):
    name=os.path.basename(fn)[:-3]
    try:
        f=h5py.File(fn)
        ops=[o.decode() for o in f['frames/op'][:]]
        t=f['passes/t_total_ms'][:]
    except Exception as e:
        print(name,'unreadable',e); continue
    tot=t[1:].mean(axis=1); o=ops[1:]
    ahead=[x for x,op in zip(tot,o) if 'ahead' in op]
    per_pass=t[1:]
    p95m=np.median([np.percentile(per_pass[:,k],95)/np.median(per_pass[:,k]) for k in range(per_pass.shape[1])])
    parts=name.split('-')
    key='-'.join(parts[:-1]) if parts[-1].startswith('r') else name
    rows[key].append((tot.mean(), np.median(tot), np.mean(ahead) if ahead else float('nan'), len(ahead), p95m))
for k in sorted(rows):
    v=np.array(rows[k])
    print('%-28s mean %s  median %.4f  ahead-frame %.4f (n=%d)  pass p95/med %.2f' % (k, ' / '.join('%.4f'%x for x in v[:,0]), v[:,1].mean(), np.nanmean(v[:,2]) if not np.all(np.isnan(v[:,2])) else float('nan'), int(v[:,3].mean()), v[:,4].mean()))
